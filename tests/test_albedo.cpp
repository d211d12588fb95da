// --albedo: the fibres' colour from a colour cross-section PNG, carried from
// the samples through the brick store to the .vdb, .vol and .nvdb outputs.
// Inputs are made here: PNGs written with libpng, straight yarns in code.
#include "core/error.h"
#include "cpu/cpu_voxelizer.h"
#include "export/fiber_grids.h"
#include "export/mitsuba_vol.h"
#include "export/nanovdb_output.h"
#include "garment/cross_section.h"
#include "gpu/gl_voxelizer.h"
#include "run_cli.h"
#include "store/brick_store.h"
#include "test_helpers.h"
#include "vdb/vdb_writer.h"

#include <catch2/catch.hpp>
#include <nanovdb/util/IO.h>
#include <openvdb/openvdb.h>
#include <png.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>

using namespace yv;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
    return yv::test::processScratchDir("yv_albedo_test") / name;
}

/// A square RGBA PNG: texel (x, y) of the cross-section (y up) gets colour(x, y),
/// alpha 255 inside the unit disk and 0 outside.
fs::path writeRgbaPng(const std::string& name, int size,
                      const std::function<std::array<std::uint8_t, 3>(int x, int y)>& colour) {
    std::vector<std::uint8_t> pixels(std::size_t(size) * size * 4);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const double u = (x + 0.5) / size * 2 - 1, v = (y + 0.5) / size * 2 - 1;
            const auto c = colour(x, y);
            // PNG rows run top to bottom.
            std::uint8_t* p = &pixels[(std::size_t(size - 1 - y) * size + x) * 4];
            p[0] = c[0], p[1] = c[1], p[2] = c[2];
            p[3] = u * u + v * v < 1.0 ? 255 : 0;
        }
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    image.width = image.height = std::uint32_t(size);
    image.format = PNG_FORMAT_RGBA;
    const fs::path path = scratch(name);
    REQUIRE(png_image_write_to_file(&image, path.c_str(), 0, pixels.data(), 0, nullptr));
    return path;
}

/// A straight yarn of radius 0.3 and length 6 along x, 6 voxels per radius.
struct StraightRun {
    SlicePlan plan;
    VoxelGrid grid;
};
StraightRun straightRun() {
    SliceOptions opt;
    opt.radius = 0.3;
    StraightRun r;
    r.plan = planSlices(test::straightYarn({0.1, 0.2, 0.3}, {1, 0, 0}, 6), opt);
    r.grid = makeGrid(r.plan, 0, opt.radius / 6.0);
    return r;
}

glm::vec3 linearColour(std::array<std::uint8_t, 3> c) {
    return {float(srgbToLinear(c[0])), float(srgbToLinear(c[1])), float(srgbToLinear(c[2]))};
}

/// Density-weighted mean albedo over a volume, and its fibre mass.
glm::dvec3 massWeightedAlbedo(const BrickVolume& v) {
    glm::dvec3 sum(0.0);
    double mass = 0.0;
    for (const VoxelBrick& b : v.bricks)
        for (int i = 0; i < kBrickVoxels; ++i)
            if (b.isActive(i)) sum += double(b.density[i]) * glm::dvec3(b.albedo[i]), mass += b.density[i];
    return sum / mass;
}

constexpr std::array<std::uint8_t, 3> kRust{200, 90, 40}, kRed{230, 20, 10}, kBlue{15, 40, 220};

/// Checks that every active voxel of `volume` has the colour `expected` and
/// every other voxel none; returns the active voxels.
std::uint64_t checkUniformAlbedo(const BrickVolume& volume, glm::vec3 expected) {
    std::uint64_t active = 0;
    for (const VoxelBrick& b : volume.bricks) {
        REQUIRE(b.albedo.size() == std::size_t(kBrickVoxels));
        for (int i = 0; i < kBrickVoxels; ++i) {
            if (!b.isActive(i)) {
                REQUIRE(b.albedo[i] == glm::vec3(0.0f));
                continue;
            }
            ++active;
            // Fixed-point rounding: at most half a unit per sample in the colour and
            // the density sums, against at least 256 units of density per sample:
            // (1 + c) / 512 at worst.
            for (int c = 0; c < 3; ++c) REQUIRE(b.albedo[i][c] == Approx(expected[c]).margin(4e-3));
        }
    }
    return active;
}

} // namespace

TEST_CASE("Albedo: sRGB to linear follows the sRGB transfer function", "[albedo]") {
    CHECK(srgbToLinear(0) == 0.0);
    CHECK(srgbToLinear(255) == Approx(1.0));
    CHECK(srgbToLinear(10) == Approx(10 / 255.0 / 12.92));           // the linear toe
    CHECK(srgbToLinear(128) == Approx(0.2158605).epsilon(1e-5));     // mid grey is about 21.6 % linear
}

TEST_CASE("Albedo: a uniformly coloured cross-section gives that colour in every voxel with fibre and none elsewhere", "[albedo]") {
    const fs::path png = writeRgbaPng("uniform.png", 32, [](int, int) { return kRust; });
    const CrossSection xs = loadCrossSectionPng(png.string(), true);
    REQUIRE(xs.hasAlbedo());
    const StraightRun run = straightRun();
    const BrickVolume volume = voxelizeCpu(run.plan, xs, run.grid, VoxelizeSettings{});
    CHECK(checkUniformAlbedo(volume, linearColour(kRust)) > 1000);

    // The same run without --albedo carries no colour at all.
    const BrickVolume plain = voxelizeCpu(run.plan, loadCrossSectionPng(png.string()), run.grid, VoxelizeSettings{});
    for (const VoxelBrick& b : plain.bricks) REQUIRE(b.albedo.empty());
    CHECK(plain.activeVoxelCount() == volume.activeVoxelCount());
}

TEST_CASE("Albedo: a two-colour cross-section gives the density-weighted mean of its colours", "[albedo]") {
    // Left half red, right half blue: the yarn's mean colour is their average
    // (equal fibre on both sides); voxels wholly on one side hold that side's colour.
    const int size = 32;
    const fs::path png = writeRgbaPng("halves.png", size, [](int x, int) { return x < size / 2 ? kRed : kBlue; });
    const CrossSection xs = loadCrossSectionPng(png.string(), true);
    const StraightRun run = straightRun();
    const BrickVolume volume = voxelizeCpu(run.plan, xs, run.grid, VoxelizeSettings{});
    const glm::dvec3 mean = massWeightedAlbedo(volume);
    const glm::dvec3 expected = 0.5 * (glm::dvec3(linearColour(kRed)) + glm::dvec3(linearColour(kBlue)));
    for (int c = 0; c < 3; ++c) CHECK(mean[c] == Approx(expected[c]).epsilon(0.02));

    int pureRed = 0, pureBlue = 0, mixed = 0;
    const glm::vec3 red = linearColour(kRed), blue = linearColour(kBlue);
    for (const VoxelBrick& b : volume.bricks)
        for (int i = 0; i < kBrickVoxels; ++i) {
            if (!b.isActive(i)) continue;
            const glm::vec3 a = b.albedo[i];
            if (glm::length(a - red) < 3e-3f) ++pureRed;
            else if (glm::length(a - blue) < 3e-3f) ++pureBlue;
            else {
                ++mixed;
                // A mix lies between the two colours on every channel.
                for (int c = 0; c < 3; ++c)
                    REQUIRE(a[c] >= std::min(red[c], blue[c]) - 4e-3f);
                for (int c = 0; c < 3; ++c)
                    REQUIRE(a[c] <= std::max(red[c], blue[c]) + 4e-3f);
            }
        }
    CHECK(pureRed > 100);
    CHECK(pureBlue > 100);
    CHECK(mixed > 0);
}

TEST_CASE("Albedo: asking for it from a grey or built-in cross-section is a clear error", "[albedo]") {
    const fs::path grey = writeRgbaPng("grey.png", 16, [](int x, int) { return std::array<std::uint8_t, 3>{std::uint8_t(x * 9), std::uint8_t(x * 9), std::uint8_t(x * 9)}; });
    CHECK_THROWS_WITH(loadCrossSectionPng(grey.string(), true),
                      Catch::Contains("--albedo needs a colour cross-section") && Catch::Contains("grey.png"));
    CHECK_NOTHROW(loadCrossSectionPng(grey.string(), false));
    CHECK_THROWS_WITH(makeCrossSection("fibers", true), Catch::Contains("--albedo") && Catch::Contains("PNG"));
    // The max reduction keeps one sample's density: it has no mean colour to keep.
    const fs::path png = writeRgbaPng("max.png", 16, [](int, int) { return kRust; });
    VoxelizeSettings max;
    max.reduce = Reduce::Max;
    const StraightRun run = straightRun();
    CHECK_THROWS_WITH(voxelizeCpu(run.plan, loadCrossSectionPng(png.string(), true), run.grid, max),
                      Catch::Contains("--albedo needs --reduce mean"));
}

TEST_CASE("Albedo: region files carry it and read it back bit-exactly", "[albedo]") {
    const fs::path png = writeRgbaPng("store.png", 32, [](int x, int) { return x < 16 ? kRed : kBlue; });
    const CrossSection coloured = loadCrossSectionPng(png.string(), true);
    const StraightRun run = straightRun();
    const BrickVolume volume = voxelizeCpu(run.plan, coloured, run.grid, VoxelizeSettings{});

    const fs::path dir = scratch("store-work");
    fs::remove_all(dir);
    StoreManifest m;
    m.fingerprint = 42;
    m.grid = run.grid;
    BrickStore store(dir.string(), m, false);
    store.writeRegion(0, glm::ivec3(0), run.grid.dims, volume.bricks);
    const std::vector<VoxelBrick> back = store.readRegion(0);
    REQUIRE(back.size() == volume.bricks.size());
    for (std::size_t i = 0; i < back.size(); ++i) {
        REQUIRE(back[i].key == volume.bricks[i].key);
        REQUIRE(back[i].albedo.size() == std::size_t(kBrickVoxels));
        REQUIRE(std::memcmp(back[i].albedo.data(), volume.bricks[i].albedo.data(), kBrickVoxels * 12) == 0);
    }
    // A region that mixes bricks with and without colour is refused.
    std::vector<VoxelBrick> mixed = volume.bricks;
    mixed.back().albedo.clear();
    CHECK_THROWS_WITH(store.writeRegion(1, glm::ivec3(0), run.grid.dims, mixed), Catch::Contains("albedo"));
    fs::remove_all(dir);

}

TEST_CASE("Albedo: the .vdb albedo grid reads back through OpenVDB and exports to .vol and .nvdb", "[albedo]") {
    const fs::path png = writeRgbaPng("vdb.png", 32, [](int x, int) { return x < 16 ? kRed : kBlue; });
    const StraightRun run = straightRun();
    const BrickVolume volume = voxelizeCpu(run.plan, loadCrossSectionPng(png.string(), true), run.grid, VoxelizeSettings{});
    const fs::path vdb = scratch("albedo.vdb");
    VdbWriteOptions options;
    options.albedo = true;
    writeVdb(vdb.string(), volume, VolumeMetadata{}, options);

    const FiberGrids grids = readFiberGrids(vdb.string());
    REQUIRE(grids.albedo);
    CHECK(grids.albedo->metaValue<std::string>("color_space") == "linear");
    CHECK(grids.albedo->activeVoxelCount() == volume.activeVoxelCount());
    CHECK(grids.albedo->transform() == grids.density->transform());
    const auto accessor = grids.albedo->getConstAccessor();
    std::uint64_t checked = 0;
    for (const VoxelBrick& b : volume.bricks) {
        const glm::ivec3 o = brickCoord(b.key) * kBrickSize;
        for (int i = 0; i < kBrickVoxels; ++i) {
            if (!b.isActive(i)) continue;
            const openvdb::Coord c(o.x + (i >> 6), o.y + ((i >> 3) & 7), o.z + (i & 7));
            REQUIRE(accessor.isValueOn(c));
            const openvdb::Vec3s a = accessor.getValue(c);
            REQUIRE(a == openvdb::Vec3s(b.albedo[i].x, b.albedo[i].y, b.albedo[i].z));
            ++checked;
        }
    }
    CHECK(checked == volume.activeVoxelCount());

    // Half precision as the orientation: within a half's rounding.
    const fs::path half = scratch("albedo-half.vdb");
    options.precision = VdbPrecision::Half;
    writeVdb(half.string(), volume, VolumeMetadata{}, options);
    const FiberGrids halfGrids = readFiberGrids(half.string());
    REQUIRE(halfGrids.albedo);
    for (auto it = halfGrids.albedo->cbeginValueOn(); it; ++it)
        for (int c = 0; c < 3; ++c) REQUIRE((*it)[c] == Approx(grids.albedo->tree().getValue(it.getCoord())[c]).epsilon(1e-3));

    // .vol: a third file of 3 channels, every voxel the grid's value (0 outside the fibre).
    const fs::path vol = scratch("albedo.vol");
    const VolExportResult r = exportMitsubaVol(grids, vol.string(), VolExportOptions{});
    REQUIRE(r.paths.size() == 3);
    CHECK(r.paths[2] == scratch("albedo.albedo.vol").string());
    std::ifstream in(r.paths[2], std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    REQUIRE(bytes.size() >= 48);
    std::int32_t header[5];
    std::memcpy(header, bytes.data() + 4, sizeof header);
    CHECK(header[0] == 1); // float32
    const glm::ivec3 dims(header[1], header[2], header[3]);
    CHECK(dims == r.box.dims());
    CHECK(header[4] == 3);
    REQUIRE(bytes.size() == 48 + std::size_t(dims.x) * dims.y * dims.z * 3 * 4);
    std::uint64_t coloured = 0;
    for (int z = 0; z < dims.z; ++z)
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x) {
                float v[3];
                std::memcpy(v, bytes.data() + 48 + ((std::size_t(z) * dims.y + y) * dims.x + x) * 12, 12);
                const openvdb::Vec3s a = accessor.getValue(openvdb::Coord(r.box.min.x + x, r.box.min.y + y, r.box.min.z + z));
                REQUIRE(v[0] == a.x());
                REQUIRE(v[1] == a.y());
                REQUIRE(v[2] == a.z());
                coloured += v[0] > 0.0f;
            }
    CHECK(coloured == volume.activeVoxelCount());

    // .nvdb: a third grid, named albedo, with the same values.
    const fs::path nvdb = scratch("albedo.nvdb");
    CHECK(exportNanoVdb(grids, nvdb.string()).grids == 3);
    const auto handle = nanovdb::io::readGrid(nvdb.string(), "albedo");
    const auto* grid = handle.grid<nanovdb::Vec3f>();
    REQUIRE(grid);
    CHECK(grid->activeVoxelCount() == volume.activeVoxelCount());
    const auto nanoAccessor = grid->getAccessor();
    for (auto it = grids.albedo->cbeginValueOn(); it; ++it) {
        const nanovdb::Vec3f a = nanoAccessor.getValue(nanovdb::Coord(it.getCoord().x(), it.getCoord().y(), it.getCoord().z()));
        REQUIRE(a[0] == (*it)[0]);
        REQUIRE(a[2] == (*it)[2]);
    }
}

TEST_CASE("Albedo: voxelize --albedo writes the grid and refuses what cannot carry it", "[albedo][cli]") {
    using test::runYarnvox;
    const fs::path bcc = scratch("cli.bcc");
    REQUIRE(runYarnvox("gen --pattern knit --crossings 4 -o " + bcc.string()).exitCode == 0);
    const fs::path png = writeRgbaPng("cli.png", 32, [](int x, int) { return x < 16 ? kRed : kBlue; });
    const fs::path grey = writeRgbaPng("cli-grey.png", 16, [](int, int) { return std::array<std::uint8_t, 3>{90, 90, 90}; });
    const std::string base = "voxelize " + bcc.string() + " --resolution 48 --quiet --cross-section ";
    const fs::path out = scratch("cli.vdb");
    fs::remove(out);

    const test::RunResult ok = runYarnvox(base + png.string() + " --albedo -o " + out.string());
    INFO(ok.output);
    REQUIRE(ok.exitCode == 0);
    const FiberGrids grids = readFiberGrids(out.string());
    REQUIRE(grids.albedo);
    CHECK(grids.albedo->activeVoxelCount() == grids.density->activeVoxelCount());

    const auto refused = [&](const std::string& args, const std::string& message) {
        const fs::path o = scratch("refused.vdb");
        fs::remove(o);
        const test::RunResult r = runYarnvox(base + args + " -o " + o.string());
        INFO(r.output);
        CHECK(r.exitCode != 0);
        CHECK(r.output.find(message) != std::string::npos);
        CHECK(!fs::exists(o));
    };
    refused(grey.string() + " --albedo", "every pixel with fibre is grey");
    refused("fibers --albedo", "--albedo");
    refused(png.string() + " --albedo --method dense", "the dense method has no albedo");
    refused(png.string() + " --albedo --reduce max", "--albedo needs --reduce mean");

    // --albedo makes another run: --resume in its work dir without it is refused, with it accepted.
    const fs::path work = scratch("cli-work");
    fs::remove_all(work);
    const std::string kept = base + png.string() + " --work-dir " + work.string() + " --keep-work-dir";
    REQUIRE(runYarnvox(kept + " --albedo -o " + out.string()).exitCode == 0);
    refused(png.string() + " --work-dir " + work.string() + " --resume", "belongs to a different run");
    const test::RunResult resumed = runYarnvox(kept + " --albedo --resume -o " + out.string());
    INFO(resumed.output);
    CHECK(resumed.exitCode == 0);
    CHECK(readFiberGrids(out.string()).albedo);
    // merge writes it too: the work dir records that the run has albedo.
    const fs::path merged = scratch("cli-merged.vdb");
    fs::remove(merged);
    REQUIRE(runYarnvox("merge " + work.string() + " -o " + merged.string()).exitCode == 0);
    const FiberGrids mergedGrids = readFiberGrids(merged.string());
    REQUIRE(mergedGrids.albedo);
    CHECK(mergedGrids.albedo->activeVoxelCount() == grids.albedo->activeVoxelCount());
    fs::remove_all(work);
}

TEST_CASE("Albedo: LOD levels keep the mass-weighted colour of the level below", "[albedo][lod]") {
    const fs::path png = writeRgbaPng("lod.png", 32, [](int x, int) { return x < 16 ? kRed : kBlue; });
    const StraightRun run = straightRun();
    const BrickVolume volume = voxelizeCpu(run.plan, loadCrossSectionPng(png.string(), true), run.grid, VoxelizeSettings{});
    const fs::path vdb = scratch("albedo-lod.vdb");
    VdbWriteOptions options;
    options.albedo = true;
    options.lodLevels = 2;
    writeVdb(vdb.string(), volume, VolumeMetadata{}, options);

    openvdb::initialize();
    openvdb::io::File file(vdb.string());
    file.open();
    const auto grid = [&](const std::string& name) {
        REQUIRE(file.hasGrid(name));
        return file.readGrid(name);
    };
    const auto density0 = openvdb::gridPtrCast<openvdb::FloatGrid>(grid("density"));
    const auto albedo0 = openvdb::gridPtrCast<openvdb::Vec3SGrid>(grid("albedo"));
    const auto density1 = openvdb::gridPtrCast<openvdb::FloatGrid>(grid("density_lod1"));
    const auto albedo1 = openvdb::gridPtrCast<openvdb::Vec3SGrid>(grid("albedo_lod1"));
    const auto albedo2 = openvdb::gridPtrCast<openvdb::Vec3SGrid>(grid("albedo_lod2"));
    file.close();
    REQUIRE((density0 && albedo0 && density1 && albedo1 && albedo2));
    CHECK(albedo1->activeVoxelCount() == density1->activeVoxelCount());
    CHECK(albedo2->metaValue<int>("lod_level") == 2);

    // Every level-1 voxel: sum over its 8 children of density * colour, over their density sum.
    const auto d0 = density0->getConstAccessor();
    const auto a0 = albedo0->getConstAccessor();
    std::uint64_t checked = 0;
    for (auto it = albedo1->cbeginValueOn(); it; ++it) {
        const openvdb::Coord p = it.getCoord();
        glm::dvec3 sum(0.0);
        double mass = 0.0;
        for (int c = 0; c < 8; ++c) {
            const openvdb::Coord q(2 * p.x() + (c >> 2), 2 * p.y() + ((c >> 1) & 1), 2 * p.z() + (c & 1));
            if (!d0.isValueOn(q)) continue;
            const double d = d0.getValue(q);
            const openvdb::Vec3s a = a0.getValue(q);
            sum += d * glm::dvec3(a.x(), a.y(), a.z()), mass += d;
        }
        REQUIRE(mass > 0.0);
        for (int c = 0; c < 3; ++c) REQUIRE((*it)[c] == Approx(sum[c] / mass).margin(1e-5));
        ++checked;
    }
    CHECK(checked > 100);
    // The whole volume's mass-weighted colour is the same at every level.
    const auto meanColour = [](const openvdb::FloatGrid& d, const openvdb::Vec3SGrid& a) {
        const auto da = d.getConstAccessor();
        glm::dvec3 sum(0.0);
        double mass = 0.0;
        for (auto it = a.cbeginValueOn(); it; ++it) {
            const double w = da.getValue(it.getCoord());
            sum += w * glm::dvec3((*it).x(), (*it).y(), (*it).z()), mass += w;
        }
        return sum / mass;
    };
    const glm::dvec3 m0 = meanColour(*density0, *albedo0), m1 = meanColour(*density1, *albedo1);
    for (int c = 0; c < 3; ++c) CHECK(m1[c] == Approx(m0[c]).epsilon(1e-4));
}

// ------------------------------------------------------------------ the GL backend

namespace {

/// Per voxel, GL against the CPU reference: the active voxels of each, and
/// the largest density and colour differences where both are active.
struct AlbedoAgreement {
    std::uint64_t both = 0, onlyCpu = 0, onlyGl = 0;
    double maxDensityDiff = 0.0, maxAlbedoDiff = 0.0;
    double densityAtMaxAlbedoDiff = 0.0; ///< the CPU's density where the colours differ most
    std::uint64_t albedoAbove1e3 = 0;    ///< voxels whose colours differ by more than 1e-3
    std::uint64_t albedoAbove1e4 = 0;    ///< voxels whose colours differ by more than 1e-4
};

AlbedoAgreement agreeWithAlbedo(const BrickVolume& cpu, const BrickVolume& gl) {
    AlbedoAgreement a;
    const test::VolumeIndex glIndex(gl), cpuIndex(cpu);
    for (const VoxelBrick& b : cpu.bricks) {
        REQUIRE(b.albedo.size() == std::size_t(kBrickVoxels));
        const glm::ivec3 origin = brickCoord(b.key) * 8;
        for (int i = 0; i < kBrickVoxels; ++i) {
            if (!b.isActive(i)) continue;
            const glm::ivec3 v = origin + glm::ivec3(i >> 6, (i >> 3) & 7, i & 7);
            const VoxelBrick* g = glIndex.brick(v);
            if (!g || !g->isActive(i)) {
                ++a.onlyCpu;
                continue;
            }
            REQUIRE(g->albedo.size() == std::size_t(kBrickVoxels));
            ++a.both;
            a.maxDensityDiff = std::max(a.maxDensityDiff, std::abs(double(g->density[i]) - double(b.density[i])));
            double diff = 0.0;
            for (int c = 0; c < 3; ++c) diff = std::max(diff, std::abs(double(g->albedo[i][c]) - double(b.albedo[i][c])));
            a.albedoAbove1e3 += diff > 1e-3;
            a.albedoAbove1e4 += diff > 1e-4;
            if (diff > a.maxAlbedoDiff) a.maxAlbedoDiff = diff, a.densityAtMaxAlbedoDiff = b.density[i];
        }
    }
    for (const VoxelBrick& g : gl.bricks) {
        const glm::ivec3 origin = brickCoord(g.key) * 8;
        for (int i = 0; i < kBrickVoxels; ++i) {
            if (!g.isActive(i)) {
                // Voxels with no fibre carry no colour, as on the CPU.
                if (!g.albedo.empty()) REQUIRE(g.albedo[i] == glm::vec3(0.0f));
                continue;
            }
            const VoxelBrick* b = cpuIndex.brick(origin + glm::ivec3(i >> 6, (i >> 3) & 7, i & 7));
            if (!b || !b->isActive(i)) ++a.onlyGl;
        }
    }
    return a;
}

GlVoxelizeSettings glAlbedoSettings(std::uint64_t capacity = 0) {
    GlVoxelizeSettings s;
    s.fragmentCapacity = capacity;
    s.brickResolve = BrickResolve::Gpu; // the GPU's path (llvmpipe would resolve on the host)
    return s;
}

} // namespace

TEST_CASE("Albedo (GL): a two-colour cross-section on a generated garment agrees with the CPU voxel by voxel", "[albedo][gl]") {
    YV_REQUIRE_GL();
    const GlContext context;
    const int size = 32;
    const fs::path png = writeRgbaPng("gl-halves.png", size, [](int x, int) { return x < size / 2 ? kRed : kBlue; });
    const CrossSection xs = loadCrossSectionPng(png.string(), true);
    const test::GeneratedRun run = test::generatedRun(WeavePattern::Knit, GarmentShape::Flat, 16, 1.0, 48);
    const BrickVolume cpu = voxelizeCpu(run.plan, xs, run.grid, VoxelizeSettings{});
    const BrickVolume gl = voxelizeGl(run.plan, xs, run.grid, glAlbedoSettings(), context);
    const AlbedoAgreement a = agreeWithAlbedo(cpu, gl);
    INFO("active in both " << a.both << ", only CPU " << a.onlyCpu << ", only GL " << a.onlyGl << "; max |GL - CPU| density "
                           << a.maxDensityDiff << ", albedo " << a.maxAlbedoDiff << " (at density "
                           << a.densityAtMaxAlbedoDiff << "), " << a.albedoAbove1e3 << " voxels' colours differ by over 1e-3, "
                           << a.albedoAbove1e4 << " by over 1e-4");
    CHECK(a.both > 2000);
    // The density tests' tolerance (test_fidelity.cpp: checkAgreement): IoU of the active sets at least 0.9999.
    CHECK(double(a.onlyCpu + a.onlyGl) <= 1e-4 * double(a.both + a.onlyCpu + a.onlyGl));
    // Float samples against double ones, then the same fixed point: a colour
    // moves by rounding only. Each backend rounds each sample's colour and
    // volume fraction by half a unit of at least 256 (kMinVoxelShare), so a
    // sliver voxel of one sample may differ by up to 2 / 512; nearly all
    // voxels hold far more and agree within 1e-3.
    CHECK(a.maxAlbedoDiff <= 2.0 / 512.0);
    CHECK(double(a.albedoAbove1e3) <= 1e-3 * double(a.both));
    // The density's rule is 99.99 % within 1e-4; a colour is a ratio of two
    // such sums, so thin voxels magnify the rounding: 99.5 % within 1e-4.
    CHECK(double(a.albedoAbove1e4) <= 5e-3 * double(a.both));
    // And so does the garment's mean colour.
    CHECK(glm::length(massWeightedAlbedo(gl) - massWeightedAlbedo(cpu)) <= 1e-4);

}

TEST_CASE("Albedo (GL): bricks drawn in several passes add their colour on the host to the same bits", "[albedo][gl][overflow]") {
    YV_REQUIRE_GL();
    const GlContext context;
    // With the smallest list, the bricks at the crossing are drawn with their
    // segments split, and their accumulators, colour words too, add up on the host.
    const test::CrossingRun run = test::crossingRun();
    const SlicePlan& plan = run.plan;
    const VoxelGrid& grid = run.grid;
    const fs::path png = writeRgbaPng("gl-split.png", 32, [](int x, int) { return x < 16 ? kRed : kBlue; });
    const CrossSection xs = loadCrossSectionPng(png.string(), true);
    GlVoxelizeCounters ample, tiny;
    const BrickVolume whole = voxelizeGl(plan, xs, grid, glAlbedoSettings(), context, &ample);
    const BrickVolume split = voxelizeGl(plan, xs, grid, glAlbedoSettings(test::smallestFragmentBudget(plan)), context, &tiny);
    INFO(tiny.hostSummedBricks << " bricks summed on the host, " << tiny.overflows << " overflows");
    CHECK(ample.hostSummedBricks == 0);
    CHECK(tiny.hostSummedBricks > 0);
    CHECK(tiny.fragments == ample.fragments);
    REQUIRE(split.bricks.size() == whole.bricks.size());
    for (std::size_t i = 0; i < whole.bricks.size(); ++i) {
        REQUIRE(split.bricks[i].key == whole.bricks[i].key);
        REQUIRE(split.bricks[i].density == whole.bricks[i].density);
        REQUIRE(split.bricks[i].albedo == whole.bricks[i].albedo);
    }
    const AlbedoAgreement a = agreeWithAlbedo(voxelizeCpu(plan, xs, grid, VoxelizeSettings{}), split);
    INFO("active in both " << a.both << ", only CPU " << a.onlyCpu << ", only GL " << a.onlyGl << "; max |GL - CPU| albedo "
                           << a.maxAlbedoDiff);
    CHECK(a.both > 1000);
    CHECK(double(a.onlyCpu + a.onlyGl) <= 1e-4 * double(a.both + a.onlyCpu + a.onlyGl));
    CHECK(a.maxAlbedoDiff <= 2.0 / 512.0);
}

TEST_CASE("Albedo (GL): a uniformly coloured straight yarn gives that colour in every voxel with fibre", "[albedo][gl]") {
    YV_REQUIRE_GL();
    const GlContext context;
    const fs::path png = writeRgbaPng("gl-uniform.png", 32, [](int, int) { return kRust; });
    const CrossSection xs = loadCrossSectionPng(png.string(), true);
    const StraightRun run = straightRun();
    const BrickVolume volume = voxelizeGl(run.plan, xs, run.grid, glAlbedoSettings(), context);
    CHECK(checkUniformAlbedo(volume, linearColour(kRust)) > 1000);
}

TEST_CASE("Albedo (GL): without it the run is what the default program makes, bit for bit", "[albedo][gl]") {
    YV_REQUIRE_GL();
    const GlContext context;
    const fs::path png = writeRgbaPng("gl-plain.png", 32, [](int x, int) { return x < 16 ? kRed : kBlue; });
    const test::GeneratedRun run = test::generatedRun(WeavePattern::Twill, GarmentShape::Flat, 16, 2.0, 40);
    GlVoxelizeCounters plainCounters, albedoCounters;
    const BrickVolume plain = voxelizeGl(run.plan, loadCrossSectionPng(png.string()), run.grid, glAlbedoSettings(), context, &plainCounters);
    const BrickVolume coloured =
        voxelizeGl(run.plan, loadCrossSectionPng(png.string(), true), run.grid, glAlbedoSettings(), context, &albedoCounters);
    // The colour rides along: the same fragments, and the same density and
    // axis bits in every brick; only the albedo run has colour.
    CHECK(plainCounters.fragments > 0);
    CHECK(plainCounters.fragments == albedoCounters.fragments);
    REQUIRE(plain.bricks.size() == coloured.bricks.size());
    for (std::size_t i = 0; i < plain.bricks.size(); ++i) {
        const VoxelBrick &p = plain.bricks[i], &c = coloured.bricks[i];
        REQUIRE(p.key == c.key);
        REQUIRE(p.activeMask == c.activeMask);
        REQUIRE(std::memcmp(p.density.data(), c.density.data(), sizeof(p.density)) == 0);
        REQUIRE(std::memcmp(p.orientation.data(), c.orientation.data(), sizeof(p.orientation)) == 0);
        REQUIRE(p.albedo.empty());
        REQUIRE(c.albedo.size() == std::size_t(kBrickVoxels));
    }
    // And the default run is still the CPU's, voxel by voxel (the existing rule).
    const BrickVolume cpu = voxelizeCpu(run.plan, loadCrossSectionPng(png.string()), run.grid, VoxelizeSettings{});
    CHECK(plain.activeVoxelCount() == cpu.activeVoxelCount());
}

TEST_CASE("Albedo (GL): voxelize --albedo --backend gl writes the albedo grid", "[albedo][gl][cli]") {
    YV_REQUIRE_GL();
    using test::runYarnvox;
    const fs::path bcc = scratch("gl-cli.bcc");
    REQUIRE(runYarnvox("gen --pattern knit --crossings 4 -o " + bcc.string()).exitCode == 0);
    const fs::path png = writeRgbaPng("gl-cli.png", 32, [](int x, int) { return x < 16 ? kRed : kBlue; });
    const std::string base = "voxelize " + bcc.string() + " --resolution 32 --quiet --albedo --cross-section " + png.string();
    const fs::path gl = scratch("gl-cli-gl.vdb"), cpu = scratch("gl-cli-cpu.vdb");
    fs::remove(gl);
    fs::remove(cpu);
    const test::RunResult r = runYarnvox(base + " --backend gl -o " + gl.string());
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    REQUIRE(runYarnvox(base + " --backend cpu -o " + cpu.string()).exitCode == 0);
    const FiberGrids glGrids = readFiberGrids(gl.string()), cpuGrids = readFiberGrids(cpu.string());
    REQUIRE(glGrids.albedo);
    REQUIRE(cpuGrids.albedo);
    CHECK(glGrids.albedo->activeVoxelCount() == glGrids.density->activeVoxelCount());
    CHECK(glGrids.albedo->activeVoxelCount() == cpuGrids.albedo->activeVoxelCount());
}

// The level-of-detail pyramid (--lod): every coarse voxel against a
// brute-force reduction of level 0 computed here, mass level to level, the
// axis over a straight yarn, the grids' metadata as renderers read it, and
// the option through the CLI.
#include "core/error.h"
#include "cpu/cpu_voxelizer.h"
#include "garment/cross_section.h"
#include "run_cli.h"
#include "test_helpers.h"
#include "vdb/lod_pyramid.h"
#include "vdb/vdb_writer.h"
#include "vdb_bytes.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <random>
#include <thread>

using namespace yv;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
    return yv::test::processScratchDir("yv_lod_test") / name;
}

/// Bricks in clusters that straddle coarse-brick boundaries at every level
/// (so parents gather children from several batches), plus lone bricks far
/// apart, with random masks, densities and axes.
BrickVolume clusteredVolume(unsigned seed) {
    BrickVolume volume;
    volume.grid.dims = {1024, 768, 512};
    volume.grid.voxelSize = 0.25;
    volume.grid.origin = {-1.0, 2.0, 0.5};
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), axis(-1.0f, 1.0f);
    std::vector<glm::ivec3> coords;
    for (int x = 6; x < 11; ++x)
        for (int y = 14; y < 18; ++y)
            for (int z = 3; z < 6; ++z) coords.push_back({x, y, z});
    coords.push_back({0, 0, 0});
    coords.push_back({127, 95, 63});
    for (int i = 0; i < 40; ++i) coords.push_back({int(rng() % 128), int(rng() % 96), int(rng() % 64)});
    std::sort(coords.begin(), coords.end(), [](glm::ivec3 a, glm::ivec3 b) { return brickKey(a) < brickKey(b); });
    coords.erase(std::unique(coords.begin(), coords.end()), coords.end());
    for (std::size_t n = 0; n < coords.size(); ++n) {
        VoxelBrick b;
        b.key = brickKey(coords[n]);
        for (int v = 0; v < kBrickVoxels; ++v) {
            if (n % 3 != 0 && rng() % 4 == 0) continue; // some bricks full, others with holes
            b.activeMask[v >> 6] |= std::uint64_t(1) << (v & 63);
            b.density[v] = unit(rng) + 1e-3f;
            b.orientation[v] = glm::vec3(canonicalAxis(glm::normalize(glm::dvec3(axis(rng), axis(rng), axis(rng)))));
        }
        volume.bricks.push_back(b);
    }
    return volume;
}

/// A coarse voxel computed directly from level 0: the sum of its level-0
/// descendants' densities and of their d a a^T.
struct BruteVoxel {
    double densitySum = 0.0;
    double tensor[6] = {0, 0, 0, 0, 0, 0};
};

std::map<std::array<int, 3>, BruteVoxel> bruteForceLevel(const BrickVolume& volume, int level) {
    std::map<std::array<int, 3>, BruteVoxel> out;
    for (const VoxelBrick& b : volume.bricks) {
        const glm::ivec3 o = brickCoord(b.key) * kBrickSize;
        for (int v = 0; v < kBrickVoxels; ++v) {
            if (!b.isActive(v)) continue;
            const glm::ivec3 p = o + glm::ivec3(v >> 6, (v >> 3) & 7, v & 7);
            BruteVoxel& c = out[{p.x >> level, p.y >> level, p.z >> level}];
            const double d = b.density[v];
            const glm::dvec3 a(b.orientation[v]);
            c.densitySum += d;
            const double t[6] = {a.x * a.x, a.y * a.y, a.z * a.z, a.x * a.y, a.x * a.z, a.y * a.z};
            for (int i = 0; i < 6; ++i) c.tensor[i] += d * t[i];
        }
    }
    return out;
}

/// The Rayleigh quotient of a symmetric 3x3 matrix (xx yy zz xy xz yz) at `a`.
double rayleigh(const double t[6], glm::dvec3 a) {
    a = glm::normalize(a);
    return t[0] * a.x * a.x + t[1] * a.y * a.y + t[2] * a.z * a.z +
           2.0 * (t[3] * a.x * a.y + t[4] * a.x * a.z + t[5] * a.y * a.z);
}

/// Its largest eigenvalue, from an eigensolver in double.
double largestEigenvalue(const double t[6]) { return rayleigh(t, principalAxis(t)); }

openvdb::GridBase::Ptr readGrid(const fs::path& path, const std::string& name) {
    openvdb::io::File file(path.string());
    file.open();
    openvdb::GridBase::Ptr g = file.readGrid(name);
    file.close();
    return g;
}

double gridMass(const openvdb::FloatGrid& g) {
    double sum = 0.0;
    for (auto it = g.cbeginValueOn(); it; ++it) sum += *it;
    const double h = g.voxelSize()[0];
    return sum * h * h * h;
}

VolumeMetadata someMetadata() {
    VolumeMetadata meta;
    meta.input = "lod test volume";
    meta.backend = "cpu";
    return meta;
}

} // namespace

TEST_CASE("LOD: each coarse voxel is the mean of its children and the principal axis of their tensors", "[vdb][lod]") {
    openvdb::initialize();
    const BrickVolume volume = clusteredVolume(11);
    REQUIRE(volume.bricks.size() > 60);
    const int levels = 3;
    const fs::path out = scratch("pyramid.vdb");
    {
        VdbWriteOptions options;
        options.lodLevels = levels;
        VdbAssembler assembler(out.string(), volume.grid, volume.reduce, options);
        // Batches that cut through clusters, from several threads: coarse
        // bricks gather their children from several of them.
        const std::span<const VoxelBrick> all(volume.bricks);
        const std::size_t cuts[] = {0, 5, 23, 24, 51, all.size()};
        std::vector<std::thread> threads;
        for (int i = 4; i >= 0; --i)
            threads.emplace_back([&, i] { assembler.add(all.subspan(cuts[i], cuts[i + 1] - cuts[i]), "batch"); });
        for (std::thread& t : threads) t.join();
        assembler.write(someMetadata());
    }
    const double h = volume.grid.voxelSize;
    const double mass0 = volume.totalMass();
    REQUIRE(mass0 > 0.0);
    for (int level = 1; level <= levels; ++level) {
        INFO("level " << level);
        auto density = openvdb::gridPtrCast<openvdb::FloatGrid>(readGrid(out, "density_lod" + std::to_string(level)));
        auto orientation =
            openvdb::gridPtrCast<openvdb::Vec3SGrid>(readGrid(out, "orientation_lod" + std::to_string(level)));
        REQUIRE(density);
        REQUIRE(orientation);
        CHECK(density->voxelSize()[0] == Approx(h * (1 << level)).epsilon(1e-12));
        const auto brute = bruteForceLevel(volume, level);
        CHECK(density->activeVoxelCount() == brute.size());
        CHECK(orientation->activeVoxelCount() == brute.size());
        CHECK(density->tree().hasSameTopology(orientation->tree()));
        const auto dAcc = density->getConstAccessor();
        const auto oAcc = orientation->getConstAccessor();
        const double children = std::pow(8.0, level);
        std::size_t wrongDensity = 0, wrongAxis = 0, notFolded = 0, inactive = 0;
        double worstDensity = 0.0, worstAxis = 0.0;
        for (const auto& [c, expect] : brute) {
            const openvdb::Coord xyz(c[0], c[1], c[2]);
            if (!dAcc.isValueOn(xyz) || !oAcc.isValueOn(xyz)) {
                ++inactive;
                continue;
            }
            // Level by level the means are rounded to float: a few ulps.
            const double want = expect.densitySum / children;
            const double rel = std::abs(dAcc.getValue(xyz) - want) / want;
            worstDensity = std::max(worstDensity, rel);
            wrongDensity += rel > 4e-7;
            // The axis is the tensor's principal one: its Rayleigh quotient
            // is the largest eigenvalue (robust where eigenvalues are close).
            const openvdb::Vec3s a = oAcc.getValue(xyz);
            const glm::dvec3 axis(a.x(), a.y(), a.z());
            const double lambda = largestEigenvalue(expect.tensor);
            const double gap = (lambda - rayleigh(expect.tensor, axis)) / lambda;
            worstAxis = std::max(worstAxis, gap);
            wrongAxis += gap > 1e-5 || std::abs(glm::length(axis) - 1.0) > 1e-6;
            notFolded += canonicalAxis(axis) != axis;
        }
        INFO("worst relative density error " << worstDensity << ", worst axis eigenvalue gap " << worstAxis);
        CHECK(inactive == 0);
        CHECK(wrongDensity == 0);
        CHECK(wrongAxis == 0);
        CHECK(notFolded == 0);
        // Mass kept level to level: density * (2^L h)^3 summed.
        CHECK(std::abs(gridMass(*density) - mass0) / mass0 < 1e-6);
    }
    fs::remove(out);
}

TEST_CASE("LOD: the pyramid's bytes do not depend on batches, threads or the order bricks come in", "[vdb][lod]") {
    openvdb::initialize();
    const BrickVolume volume = clusteredVolume(5);
    VdbWriteOptions options;
    options.lodLevels = 2;
    const fs::path whole = scratch("whole.vdb"), batches = scratch("batches.vdb");
    writeVdb(whole.string(), volume, someMetadata(), options);
    {
        VdbAssembler assembler(batches.string(), volume.grid, volume.reduce, options);
        std::vector<VoxelBrick> shuffled = volume.bricks;
        std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(3));
        for (std::size_t i = 0; i < shuffled.size(); i += 7)
            assembler.add(std::span(shuffled).subspan(i, std::min<std::size_t>(7, shuffled.size() - i)), "batch");
        assembler.write(someMetadata());
    }
    const bool sameBytes = test::vdbBytesWithoutUuid(whole) == test::vdbBytesWithoutUuid(batches);
    CHECK(sameBytes);
    fs::remove(whole);
    fs::remove(batches);
}

TEST_CASE("LOD: over a straight yarn at an angle every coarse voxel's axis is the yarn's", "[vdb][lod][cpu]") {
    openvdb::initialize();
    const glm::dvec3 axis = glm::normalize(glm::dvec3(1.0, 0.45, -0.3));
    SliceOptions opt;
    opt.radius = 0.3;
    const SlicePlan plan = planSlices(test::straightYarn({0.1, 0.2, 0.3}, axis, 6), opt);
    const VoxelGrid grid = makeGrid(plan, 0, opt.radius / 6.0);
    VoxelizeSettings settings;
    const BrickVolume volume = voxelizeCpu(plan, makeDiskCrossSection(), grid, settings);
    REQUIRE(volume.activeVoxelCount() > 1000);
    VdbWriteOptions options;
    options.lodLevels = 2;
    const fs::path out = scratch("yarn.vdb");
    writeVdb(out.string(), volume, someMetadata(), options);
    for (int level = 1; level <= 2; ++level) {
        INFO("level " << level);
        auto density = openvdb::gridPtrCast<openvdb::FloatGrid>(readGrid(out, "density_lod" + std::to_string(level)));
        auto orientation =
            openvdb::gridPtrCast<openvdb::Vec3SGrid>(readGrid(out, "orientation_lod" + std::to_string(level)));
        REQUIRE(orientation->activeVoxelCount() > 20);
        const auto dAcc = density->getConstAccessor();
        double worst = 0.0;
        for (auto it = orientation->cbeginValueOn(); it; ++it) {
            // As at level 0: a sliver of fibre holds too few fixed-point units for an axis.
            if (dAcc.getValue(it.getCoord()) < 1e-3f) continue;
            const glm::dvec3 a((*it).x(), (*it).y(), (*it).z());
            worst = std::max(worst, std::acos(std::min(1.0, std::abs(glm::dot(a, axis)))));
        }
        CHECK(worst * 180.0 / M_PI < 0.5);
        CHECK(std::abs(gridMass(*density) - volume.totalMass()) / volume.totalMass() < 1e-6);
    }
    fs::remove(out);
}

TEST_CASE("LOD: grids carry what renderers read, and coarse voxels nest in level 0's", "[vdb][lod][metadata]") {
    openvdb::initialize();
    const BrickVolume volume = clusteredVolume(2);
    VdbWriteOptions options;
    options.lodLevels = 2;
    options.precision = VdbPrecision::Half;
    const fs::path out = scratch("metadata.vdb");
    writeVdb(out.string(), volume, someMetadata(), options);
    openvdb::io::File file(out.string());
    file.open();
    const auto meta = file.getMetadata();
    CHECK(meta->metaValue<std::int32_t>("lod_levels") == 2);
    const char* names[] = {"density", "orientation", "density_lod1", "orientation_lod1", "density_lod2", "orientation_lod2"};
    CHECK(file.getGrids()->size() == 6);
    const double h = volume.grid.voxelSize;
    for (std::size_t i = 0; i < 6; ++i) {
        REQUIRE(file.hasGrid(names[i]));
        const openvdb::GridBase::Ptr grid = file.readGrid(names[i]);
        const openvdb::GridBase& g = *grid;
        const int level = int(i / 2);
        INFO(names[i]);
        CHECK(g.getName() == names[i]);
        CHECK(g.saveFloatAsHalf());
        if (i % 2 == 0) {
            // Blender, Houdini and pbrt take a float grid named "density" as a fog volume.
            CHECK(g.isType<openvdb::FloatGrid>());
            CHECK(g.getGridClass() == openvdb::GRID_FOG_VOLUME);
        } else {
            // A vec3 grid Blender imports as a vector attribute; invariant: an axis, not moved like a position.
            CHECK(g.isType<openvdb::Vec3SGrid>());
            CHECK(g.getVectorType() == openvdb::VEC_INVARIANT);
        }
        if (level > 0)
            CHECK(g.metaValue<std::int32_t>("lod_level") == level);
        else
            CHECK_FALSE(g.getMetadata<openvdb::Int32Metadata>("lod_level"));
        // Voxel (i, j, k) of level L covers origin + [2^L i, 2^L (i + 1)) h.
        const double hl = h * (1 << level);
        const openvdb::Vec3d c = g.transform().indexToWorld(openvdb::Coord(3, 1, 2));
        CHECK(c.x() == Approx(volume.grid.origin.x + 3.5 * hl).epsilon(1e-12));
        CHECK(c.y() == Approx(volume.grid.origin.y + 1.5 * hl).epsilon(1e-12));
        CHECK(c.z() == Approx(volume.grid.origin.z + 2.5 * hl).epsilon(1e-12));
    }
    file.close();
    fs::remove(out);
}

TEST_CASE("LOD: a grid too small for the levels asked for is refused before anything is written", "[vdb][lod]") {
    VoxelGrid grid;
    grid.dims = {64, 32, 16};
    CHECK(maxLodLevels(grid) == 3);
    CHECK(checkedLodLevels(3, grid) == 3);
    try {
        checkedLodLevels(4, grid);
        FAIL("no error");
    } catch (const Error& e) {
        CHECK(std::string(e.what()) == "--lod 4: the grid is 64 voxels on its longest axis, and every level must keep "
                                       "at least 8 (one brick): give --lod 0 to 3");
    }
    const fs::path out = scratch("refused.vdb");
    fs::remove(out);
    VdbWriteOptions options;
    options.lodLevels = 4;
    CHECK_THROWS_AS(VdbAssembler(out.string(), grid, Reduce::Mean, options), Error);
    CHECK_FALSE(fs::exists(out));
}

TEST_CASE("CLI: voxelize --lod writes the pyramid, and refuses levels the grid cannot have", "[cli][lod]") {
    openvdb::initialize();
    const fs::path bcc = scratch("knit.bcc"), vdb = scratch("knit.vdb"), plain = scratch("plain.vdb");
    fs::remove(vdb);
    REQUIRE(test::runYarnvox("gen --pattern knit --crossings 40 --shape cylinder --seed 2 -o " + bcc.string()).exitCode == 0);
    // Float values: each level keeps level 0's fibre volume to float rounding.
    const test::RunResult lod = test::runYarnvox("voxelize " + bcc.string() + " -o " + vdb.string() +
                                                 " --backend cpu --resolution 64 --lod 3 --precision float --quiet");
    INFO(lod.output);
    REQUIRE(lod.exitCode == 0);
    const test::RunResult none = test::runYarnvox("voxelize " + bcc.string() + " -o " + plain.string() +
                                                  " --backend cpu --resolution 64 --precision float --quiet");
    REQUIRE(none.exitCode == 0);
    openvdb::io::File file(vdb.string());
    file.open();
    CHECK(file.getGrids()->size() == 8);
    for (const char* name : {"density_lod3", "orientation_lod3"}) CHECK(file.hasGrid(name));
    // Level 0 is the file without --lod's.
    auto d0 = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("density"));
    auto plainDensity = openvdb::gridPtrCast<openvdb::FloatGrid>(readGrid(plain, "density"));
    CHECK(d0->tree().hasSameTopology(plainDensity->tree()));
    const double mass0 = gridMass(*d0);
    for (int level = 1; level <= 3; ++level) {
        auto d = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("density_lod" + std::to_string(level)));
        REQUIRE(d);
        INFO("level " << level);
        CHECK(d->activeVoxelCount() > 0);
        CHECK(std::abs(gridMass(*d) - mass0) / mass0 < 1e-6);
    }
    file.close();
    // OpenVDB's own tool reads every grid.
    const test::RunResult print = test::runShell("vdb_print -l " + vdb.string());
    INFO(print.output);
    CHECK(print.exitCode == 0);
    for (const char* name : {"Name: density_lod3", "Name: orientation_lod3", "lod_level: 3", "class: fog volume"})
        CHECK(print.output.find(name) != std::string::npos);

    const fs::path refused = scratch("refused.vdb");
    fs::remove(refused);
    const test::RunResult bad = test::runYarnvox("voxelize " + bcc.string() + " -o " + refused.string() +
                                                 " --backend cpu --resolution 64 --lod 4 --quiet");
    INFO(bad.output);
    CHECK(bad.exitCode != 0);
    CHECK(bad.output.find("yarnvox: error: --lod 4: the grid is ") == 0);
    CHECK(bad.output.find("give --lod 0 to 3") != std::string::npos);
    CHECK(std::count(bad.output.begin(), bad.output.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(refused));
    const test::RunResult negative = test::runYarnvox("voxelize " + bcc.string() + " -o " + refused.string() +
                                                      " --backend cpu --resolution 64 --lod -1");
    CHECK(negative.exitCode != 0);
    CHECK_FALSE(fs::exists(refused));
}

TEST_CASE("CLI: merge --lod gives the file voxelize --lod gave, and refuses levels the grid cannot have", "[gl][cli][lod]") {
    YV_REQUIRE_GL();
    const fs::path bcc = scratch("plain.bcc"), work = scratch("plain.work"), direct = scratch("direct.vdb"),
                   merged = scratch("merged.vdb"), refused = scratch("merge-refused.vdb");
    fs::remove_all(work);
    for (const fs::path& p : {direct, merged, refused}) fs::remove(p);
    REQUIRE(test::runYarnvox("gen --pattern plain --crossings 16 -o " + bcc.string()).exitCode == 0);
    const test::RunResult voxelize = test::runYarnvox("voxelize " + bcc.string() + " -o " + direct.string() +
                                                      " --backend gl --resolution 32 --lod 2 --quiet --work-dir " +
                                                      work.string());
    INFO(voxelize.output);
    REQUIRE(voxelize.exitCode == 0);
    const test::RunResult merge = test::runYarnvox("merge " + work.string() + " -o " + merged.string() + " --lod 2 --quiet");
    INFO(merge.output);
    REQUIRE(merge.exitCode == 0);
    const bool sameBytes = test::vdbBytesWithoutUuid(direct) == test::vdbBytesWithoutUuid(merged);
    CHECK(sameBytes);
    openvdb::initialize();
    CHECK(readGrid(merged, "density_lod2")->activeVoxelCount() > 0);

    const test::RunResult bad = test::runYarnvox("merge " + work.string() + " -o " + refused.string() + " --lod 9");
    INFO(bad.output);
    CHECK(bad.exitCode == 1);
    CHECK(bad.output.find("yarnvox: error: --lod 9: the grid is ") == 0);
    CHECK(std::count(bad.output.begin(), bad.output.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(refused));
    fs::remove_all(work);
}

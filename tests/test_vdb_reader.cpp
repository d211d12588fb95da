// yarnvox's own .vdb reader (vdb/vdb_index.h, inspect's vdb_subset_source):
// what it reads equals what OpenVDB reads from the same file, voxel for
// voxel and pixel for pixel; files outside the subset still open (through
// OpenVDB); a truncated or damaged file is refused with one line.
#include "core/error.h"
#include "inspect/brick_level.h"
#include "inspect/inspect_vdb.h"
#include "inspect/volume_source.h"
#include "inspect_test_volumes.h"
#include "render/render_context.h"
#include "render/render_volume.h"
#include "run_cli.h"
#include "test_helpers.h"
#include "vdb/vdb_index.h"
#include "vdb/vdb_writer.h"

#include <catch2/catch.hpp>
#include <openvdb/openvdb.h>

#include <climits>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>

using namespace yv;
namespace fs = std::filesystem;

namespace {

struct Scratch : test::ScratchDir {
    Scratch() : test::ScratchDir("yv_test_vdb_reader") {}
};

constexpr glm::ivec3 kAll0{INT_MIN / 2}, kAll1{INT_MAX / 2};

/// Bricks over several root children (a root child spans 4096 voxels), some
/// full, some with a few voxels, random values and unit axes.
BrickVolume scatteredVolume() {
    BrickVolume v;
    v.grid.voxelSize = 0.05;
    v.grid.dims = glm::ivec3(8200, 96, 4200);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const glm::ivec3 starts[] = {{0, 0, 0}, {500, 3, 7}, {1020, 0, 520}};
    for (const glm::ivec3& s : starts)
        for (int i = 0; i < 60; ++i) {
            const glm::ivec3 c = s + glm::ivec3(i % 5, (i / 5) % 4, i / 20);
            VoxelBrick b;
            b.key = brickKey(c);
            const bool sparse = i % 3 == 1;
            for (int vox = 0; vox < kBrickVoxels; ++vox) {
                if (sparse && vox % 37 != 0) continue;
                b.activeMask[vox >> 6] |= std::uint64_t(1) << (vox & 63);
                b.density[vox] = 0.01f + unit(rng);
                b.orientation[vox] = glm::normalize(glm::vec3(unit(rng) - 0.5f, unit(rng) - 0.5f, unit(rng) + 0.1f));
            }
            v.bricks.push_back(b);
        }
    std::sort(v.bricks.begin(), v.bricks.end(), [](const VoxelBrick& a, const VoxelBrick& b) { return a.key < b.key; });
    return v;
}

struct ReadBrick {
    std::vector<float> density;
    std::vector<glm::vec3> axes;
};

/// Every brick `source` gives at stored level `level`, by coordinate.
std::map<std::uint64_t, ReadBrick> readAll(const VolumeSource& source, int level) {
    std::map<std::uint64_t, ReadBrick> out;
    source.forEachLevelBrick(level, kAll0, kAll1, [&](const SourceBrick& b) {
        ReadBrick& r = out[brickKey(b.coord)];
        r.density.assign(b.density, b.density + kBrickVoxels);
        if (b.orientation) r.axes.assign(b.orientation, b.orientation + kBrickVoxels);
    });
    return out;
}

/// The same read by OpenVDB from grid `name`/`axesName` of `path`.
std::map<std::uint64_t, ReadBrick> readThroughOpenVdb(const std::string& path, const std::string& name,
                                                      const std::string& axesName) {
    openvdb::initialize();
    openvdb::io::File file(path);
    file.open();
    auto density = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid(name));
    auto axes = openvdb::gridPtrCast<openvdb::Vec3SGrid>(file.readGrid(axesName));
    file.close();
    std::map<std::uint64_t, ReadBrick> out;
    for (auto leaf = density->tree().cbeginLeaf(); leaf; ++leaf) {
        const openvdb::Coord o = leaf->origin();
        ReadBrick& r = out[brickKey(glm::ivec3(o.x(), o.y(), o.z()) / 8)];
        const auto* a = axes->tree().probeConstLeaf(o);
        REQUIRE(a);
        for (int v = 0; v < kBrickVoxels; ++v) {
            r.density.push_back(leaf->isValueOn(openvdb::Index(v)) ? leaf->getValue(openvdb::Index(v)) : 0.0f);
            const openvdb::Vec3s x = a->getValue(openvdb::Index(v));
            r.axes.push_back(leaf->isValueOn(openvdb::Index(v)) ? glm::vec3(x.x(), x.y(), x.z()) : glm::vec3(0.0f));
        }
    }
    return out;
}

void requireSame(const std::map<std::uint64_t, ReadBrick>& a, const std::map<std::uint64_t, ReadBrick>& b) {
    REQUIRE(a.size() == b.size());
    int wrong = 0;
    for (auto i = a.begin(), j = b.begin(); i != a.end(); ++i, ++j) {
        REQUIRE(i->first == j->first);
        for (int v = 0; v < kBrickVoxels; ++v) {
            const bool same = i->second.density[v] == j->second.density[v] &&
                              (i->second.density[v] == 0.0f || i->second.axes[v] == j->second.axes[v]);
            if (!same && ++wrong < 4)
                WARN("brick " << i->first << " voxel " << v << ": " << i->second.density[v] << " against "
                              << j->second.density[v]);
        }
    }
    CHECK(wrong == 0);
}

std::string writeScattered(const fs::path& dir, VdbPrecision precision, int lod) {
    const std::string path = (dir / ("v-" + std::string(toString(precision)) + std::to_string(lod) + ".vdb")).string();
    VdbWriteOptions options;
    options.precision = precision;
    options.lodLevels = lod;
    writeVdb(path, scatteredVolume(), VolumeMetadata{}, options);
    return path;
}

void truncateTo(const std::string& from, const std::string& to, std::uintmax_t bytes) {
    fs::copy_file(from, to, fs::copy_options::overwrite_existing);
    fs::resize_file(to, bytes);
}

void putByte(const std::string& path, std::uint64_t at, std::uint8_t value) {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(std::streamoff(at));
    f.put(char(value));
}

/// The message of the yv::Error `f` throws ("" when it throws none).
template <typename F> std::string errorOf(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST_CASE("vdb reader: every leaf of every level equals OpenVDB's reading of the same file, float and half",
          "[vdb][reader]") {
    Scratch scratch;
    for (VdbPrecision precision : {VdbPrecision::Float, VdbPrecision::Half}) {
        const std::string path = writeScattered(scratch.path, precision, 2);
        const VdbIndex index(path);
        REQUIRE(index.inSubset());
        const auto source = openVdbSource(path);
        CHECK(source->storedLevels() == std::vector<int>{0, 1, 2});
        CHECK(source->hasOrientation());
        requireSame(readAll(*source, 0), readThroughOpenVdb(path, "density", "orientation"));
        for (int level : {1, 2}) {
            const std::string suffix = "_lod" + std::to_string(level);
            requireSame(readAll(*source, level), readThroughOpenVdb(path, "density" + suffix, "orientation" + suffix));
        }
        // The OpenVDB source lists the same bricks and bounds.
        const auto throughOpenVdb = openVdbSourceThroughOpenVdb(path);
        CHECK(source->occupiedBricks() == throughOpenVdb->occupiedBricks());
        CHECK(source->bounds().min == throughOpenVdb->bounds().min);
        CHECK(source->bounds().max == throughOpenVdb->bounds().max);
    }
}

TEST_CASE("vdb reader: inspect's numbers for a yarnvox .vdb count every voxel the volume has", "[vdb][reader]") {
    Scratch scratch;
    const BrickVolume volume = scatteredVolume();
    const std::string path = writeScattered(scratch.path, VdbPrecision::Float, 0);
    const VdbSummary s = inspectVdb(path);
    VoxelStatistics expected;
    for (const VoxelBrick& b : volume.bricks) expected.addBrick(b.density.data(), b.orientation.data(), b.activeMask.data());
    CHECK(s.voxels.activeVoxels == expected.activeVoxels);
    CHECK(s.voxels.histogram == expected.histogram);
    CHECK(s.voxels.unitAxes == expected.unitAxes);
    CHECK(s.voxels.densitySum() == Approx(expected.densitySum()).epsilon(1e-12));
    CHECK(s.voxels == expected); // the sums are exact whatever the order: every bit
    REQUIRE(s.grids.size() == 2);
    CHECK(s.grids[0].leaves == volume.bricks.size());
    CHECK(s.grids[0].activeVoxels == expected.activeVoxels);
    CHECK(s.hasOrientation);
    CHECK(s.libraryVersion == "10.0/224");
}

TEST_CASE("vdb reader: a .vdb written by OpenVDB itself (blosc, zip, grids in another order) opens through OpenVDB",
          "[vdb][reader]") {
    Scratch scratch;
    const BrickVolume volume = scatteredVolume();
    const std::string own = writeScattered(scratch.path, VdbPrecision::Float, 0);
    openvdb::initialize();
    openvdb::io::File in(own);
    in.open();
    const openvdb::GridPtrVecPtr grids = in.getGrids();
    in.close();
    openvdb::GridPtrVec reordered{(*grids)[1], (*grids)[0]}; // orientation first
    std::vector<std::uint32_t> codecs{openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK};
    if (openvdb::io::Archive::hasBloscCompression())
        codecs.push_back(openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK);
    for (std::uint32_t codec : codecs) {
        const std::string path = (scratch.path / ("openvdb-" + std::to_string(codec) + ".vdb")).string();
        openvdb::io::File out(path);
        out.setCompression(codec);
        out.write(reordered);
        out.close();
        CHECK_FALSE(VdbIndex(path).inSubset());
        const auto source = openVdbSource(path);
        requireSame(readAll(*source, 0), readAll(*openVdbSource(own), 0));
        CHECK(inspectVdb(path).voxels.activeVoxels == volume.activeVoxelCount());
    }
}

TEST_CASE("vdb reader: a volume rendered from the reader equals the same volume rendered through OpenVDB",
          "[vdb][reader][gl]") {
    YV_REQUIRE_GL();
    Scratch scratch;
    const std::string path = (scratch.path / "knit.vdb").string();
    writeVdb(path, test::knitCylinderVolume(96), VolumeMetadata{});
    RenderContext context;
    for (RenderKind kind : {RenderKind::Raycast, RenderKind::Orientation, RenderKind::Mip})
        for (std::uint64_t budget : {std::uint64_t(1) << 30, std::uint64_t(1) << 20}) { // full, then a reduced level
            RenderRequest r;
            r.kind = kind;
            r.width = 160, r.height = 120;
            r.gpuBudgetBytes = budget;
            const RenderReport own = renderVolume(context, *openVdbSource(path), r);
            const RenderReport reference = renderVolume(context, *openVdbSourceThroughOpenVdb(path), r);
            CHECK(own.level == reference.level);
            CHECK(own.levelBricks == reference.levelBricks);
            CHECK(own.image.pixels == reference.image.pixels);
            CHECK(std::count_if(own.image.pixels.begin(), own.image.pixels.end(), [](std::uint8_t p) { return p; }) > 100);
        }
}

TEST_CASE("vdb reader: a file with a pyramid is drawn from its stored level, never reading level 0", "[vdb][reader][gl]") {
    YV_REQUIRE_GL();
    Scratch scratch;
    const std::string path = (scratch.path / "knit-lod.vdb").string();
    VdbWriteOptions options;
    options.lodLevels = 2;
    const BrickVolume volume = test::knitCylinderVolume(96);
    writeVdb(path, volume, VolumeMetadata{}, options);
    // Level 0 damaged: a render that reads it fails, one drawn from level 2 does not.
    const VdbIndex index(path);
    putByte(path, index.grid("density")->blockPos + 64, 9); // leaf 0's metadata byte
    RenderContext context;
    RenderRequest r;
    r.width = 160, r.height = 120;
    r.gpuBudgetBytes = levelGpuBytes(volume.bricks.size(), glm::ivec3(1), 2) / 4; // below level 0's bricks
    const RenderReport coarse = renderVolume(context, *openVdbSource(path), r);
    CHECK(coarse.storedLevel);
    CHECK(coarse.level >= 1);
    r.gpuBudgetBytes = 1ull << 30;
    const std::string message = errorOf([&] { renderVolume(context, *openVdbSource(path), r); });
    CHECK_THAT(message, Catch::Contains("leaf 0"));
}

TEST_CASE("vdb reader: a truncated or damaged .vdb is refused with one line naming the file and where",
          "[vdb][reader]") {
    Scratch scratch;
    const std::string good = writeScattered(scratch.path, VdbPrecision::Float, 0);
    const auto size = fs::file_size(good);
    const auto readWhole = [](const std::string& path) {
        const auto source = openVdbSource(path);
        readAll(*source, 0);
    };
    for (std::uintmax_t keep : {size - 1, size / 2, std::uintmax_t(200), std::uintmax_t(40)}) {
        const std::string cut = (scratch.path / ("cut-" + std::to_string(keep) + ".vdb")).string();
        truncateTo(good, cut, keep);
        const std::string message = errorOf([&] { readWhole(cut); });
        INFO("kept " << keep << " bytes: " << message);
        CHECK_THAT(message, Catch::Contains(cut));
        CHECK(message.find('\n') == std::string::npos);
        CHECK(message.size() < 400);
        const std::string summary = errorOf([&] { inspectVdb(cut); });
        CHECK_THAT(summary, Catch::Contains(cut));
    }
    const VdbIndex index(good);
    const VdbGridInfo& density = *index.grid("density");
    const VdbLeafTable leaves = index.leaves(density);
    struct Damage {
        std::uint64_t at;
        std::uint8_t value;
        const char* names;
    };
    const Damage damages[] = {
        {density.topologyPos + 12, 0xff, "root child count"},  // the child count's low byte
        {density.topologyPos + 4, 0x7f, "background"},          // a background that is not 0
        {leaves.records[3] + 64, 5, "leaf 3"},                  // a leaf's metadata byte
        {leaves.records[5] + 65, 0xff, "leaf 5"},               // a NaN in a leaf's first value
    };
    for (const Damage& d : damages) {
        const std::string bad = (scratch.path / "bad.vdb").string();
        fs::copy_file(good, bad, fs::copy_options::overwrite_existing);
        putByte(bad, d.at, d.value);
        if (std::string(d.names) == "leaf 5") {
            for (int k = 0; k < 4; ++k) putByte(bad, d.at + k, k == 3 ? 0x7f : 0xff); // one float: NaN
        }
        const std::string message = errorOf([&] { readWhole(bad); });
        INFO("damage at byte " << d.at << ": " << message);
        CHECK_THAT(message, Catch::Contains(bad) && Catch::Contains(d.names));
        CHECK(message.find('\n') == std::string::npos);
        CHECK(message.size() < 400);
    }
}

TEST_CASE("vdb reader: inspect refuses a cut .vdb in one line, and writes no picture", "[vdb][reader][cli]") {
    Scratch scratch;
    const std::string good = writeScattered(scratch.path, VdbPrecision::Half, 1);
    const std::string cut = (scratch.path / "cut.vdb").string();
    truncateTo(good, cut, fs::file_size(good) - 1);
    const std::string png = (scratch.path / "p.png").string();
    for (const std::string& args : {"inspect " + cut, "inspect " + cut + " --render raycast -o " + png}) {
        const test::RunResult r = test::runYarnvox(args);
        INFO(args << ": " << r.output);
        CHECK(r.exitCode != 0);
        CHECK_THAT(r.output, Catch::StartsWith("yarnvox: error: " + cut));
        CHECK(std::count(r.output.begin(), r.output.end(), '\n') == 1);
    }
    CHECK_FALSE(fs::exists(png));
}

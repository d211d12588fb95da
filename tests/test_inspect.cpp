// `yarnvox inspect`: its numbers against what was written, and --verify
// against a damaged region.
#include "core/error.h"
#include "cpu/cpu_voxelizer.h"
#include "garment/cross_section.h"
#include "garment/generate.h"
#include "garment/slices.h"
#include "inspect/inspect_store.h"
#include "inspect/inspect_vdb.h"
#include "run_cli.h"
#include "vdb/vdb_writer.h"

#include <catch2/catch.hpp>
#include <openvdb/openvdb.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>

using namespace yv;
namespace fs = std::filesystem;

namespace {

struct Scratch {
    fs::path path;
    Scratch() {
        path = fs::temp_directory_path() / ("yv_test_inspect_" + std::to_string(::getpid()) + "_" + std::to_string(std::random_device{}()));
        fs::create_directories(path);
    }
    ~Scratch() { fs::remove_all(path); }
};

/// A generated garment voxelized on the CPU, written as a work directory of
/// four regions (the grid cut in halves along x and y).
BrickVolume writeFourRegionStore(const std::string& dir) {
    GenerateOptions gen;
    gen.crossings = 200;
    const Garment garment = generateGarment(gen);
    SliceOptions opt;
    opt.radius = garment.yarnRadius;
    const SlicePlan plan = planSlices(garment, opt);
    const VoxelGrid grid = makeGrid(plan, 96, 0.0);
    const BrickVolume volume = voxelizeCpu(plan, makeFiberCrossSection(), grid, VoxelizeSettings{});
    StoreManifest manifest;
    manifest.fingerprint = 42;
    manifest.grid = grid;
    manifest.run.input = "generated", manifest.run.backend = "cpu";
    BrickStore store(dir, manifest, false);
    const glm::ivec3 size = (grid.dims + 7) / 8 * 8;
    const glm::ivec3 half(size.x / 16 * 8, size.y / 16 * 8, size.z);
    for (int r = 0; r < 4; ++r) {
        const glm::ivec3 min((r & 1) * half.x, (r >> 1) * half.y, 0);
        const glm::ivec3 max((r & 1) ? size.x : half.x, (r >> 1) ? size.y : half.y, size.z);
        std::vector<VoxelBrick> bricks;
        for (const VoxelBrick& b : volume.bricks) {
            const glm::ivec3 o = brickCoord(b.key) * 8;
            if (o.x >= min.x && o.x < max.x && o.y >= min.y && o.y < max.y) bricks.push_back(b);
        }
        store.writeRegion(std::uint64_t(r), min, max, bricks);
    }
    store.markComplete(4);
    return volume;
}

} // namespace

TEST_CASE("inspect: the region table's totals are the store's, and verifying reads every voxel", "[inspect]") {
    Scratch scratch;
    const std::string dir = (scratch.path / "work").string();
    const BrickVolume volume = writeFourRegionStore(dir);
    REQUIRE(volume.bricks.size() > 20);

    const StoreSummary quick = inspectStore(dir, false);
    REQUIRE(quick.regions.size() == 4);
    CHECK(quick.badRegions == 0);
    CHECK(quick.bricks == volume.bricks.size());
    CHECK(quick.activeVoxels == volume.activeVoxelCount());
    CHECK(quick.bytesOnDisk == BrickStore(dir).bytesOnDisk());
    std::uint64_t rows = 0;
    for (const RegionRow& r : quick.regions) rows += r.info.activeVoxels;
    CHECK(rows == quick.activeVoxels);
    CHECK(quick.voxels.activeVoxels == 0); // not read without --verify

    const StoreSummary full = inspectStore(dir, true);
    CHECK(full.badRegions == 0);
    CHECK(full.voxels.activeVoxels == volume.activeVoxelCount());
    std::uint64_t binned = 0;
    for (std::uint64_t n : full.voxels.histogram) binned += n;
    CHECK(binned == volume.activeVoxelCount());
    double mass = 0.0;
    for (const VoxelBrick& b : volume.bricks)
        for (int v = 0; v < kBrickVoxels; ++v)
            if (b.isActive(v)) mass += b.density[v];
    CHECK(full.voxels.densitySum() == Approx(mass).epsilon(1e-12));
    CHECK(full.voxels.unitAxes == volume.activeVoxelCount());

    // The CLI prints the same totals.
    const test::RunResult r = test::runYarnvox("inspect " + dir + " --sort active --limit 2");
    INFO(r.output);
    CHECK(r.exitCode == 0);
    CHECK(r.output.find("4 regions (run complete), " + std::to_string(volume.bricks.size()) + " bricks, " +
                        std::to_string(volume.activeVoxelCount()) + " active voxels") != std::string::npos);
    CHECK(r.output.find("(2 more;") != std::string::npos);
}

TEST_CASE("inspect --verify finds a flipped byte and names the region", "[inspect]") {
    Scratch scratch;
    const std::string dir = (scratch.path / "work").string();
    writeFourRegionStore(dir);
    const std::string victim = BrickStore(dir).regionPath(2);
    const auto size = fs::file_size(victim);
    {
        std::fstream f(victim, std::ios::in | std::ios::out | std::ios::binary);
        f.seekg(std::streamoff(size - 40));
        char c = 0;
        f.get(c);
        f.seekp(std::streamoff(size - 40));
        f.put(char(c ^ 0x10));
    }
    const test::RunResult verified = test::runYarnvox("inspect " + dir + " --verify");
    INFO(verified.output);
    CHECK(verified.exitCode == 1);
    CHECK(verified.output.find("1 of 4 regions are damaged") != std::string::npos);
    CHECK(verified.output.find(victim) != std::string::npos);
    const StoreSummary s = inspectStore(dir, true);
    CHECK(s.badRegions == 1);
    for (const RegionRow& row : s.regions) CHECK(row.problem.empty() == (row.info.id != 2));
    CHECK(fs::exists(victim)); // inspection never deletes
}

TEST_CASE("inspect of a .vdb: histogram, voxels above one, mass and axes", "[inspect]") {
    Scratch scratch;
    BrickVolume volume;
    volume.grid.dims = {32, 32, 32};
    volume.grid.voxelSize = 0.5;
    // 100 voxels of 0.05, 50 of 1.0, 10 of 1.5; every axis along y.
    VoxelBrick a, b;
    a.key = brickKey({0, 0, 0});
    b.key = brickKey({2, 1, 3});
    for (int v = 0; v < 160; ++v) {
        VoxelBrick& brick = v < 100 ? a : b;
        const int at = v < 100 ? v : v - 100;
        brick.activeMask[std::size_t(at >> 6)] |= std::uint64_t(1) << (at & 63);
        brick.density[std::size_t(at)] = v < 100 ? 0.05f : v < 150 ? 1.0f : 1.5f;
        brick.orientation[std::size_t(at)] = {0.0f, 1.0f, 0.0f};
    }
    volume.bricks = {a, b};
    const std::string path = (scratch.path / "known.vdb").string();
    writeVdb(path, volume, VolumeMetadata{});

    const VdbSummary s = inspectVdb(path);
    REQUIRE(s.grids.size() == 2);
    CHECK(s.hasOrientation);
    CHECK(s.grids[0].activeVoxels == 160);
    CHECK(s.grids[0].leaves == 2);
    CHECK(s.voxels.activeVoxels == 160);
    CHECK(s.voxels.histogram[0] == 100);
    CHECK(s.voxels.histogram[9] == 50);
    CHECK(s.voxels.histogram[10] == 10);
    CHECK(s.voxels.aboveOne == 10);
    CHECK(s.voxels.densityMax == 1.5);
    CHECK(s.voxels.densitySum() == Approx(100 * 0.05 + 50 + 15).epsilon(1e-6));
    CHECK(s.voxels.unitAxes == 160);
    CHECK(s.voxels.axisComponentSum().y == Approx(160.0));

    // Anyone's file with only a float density grid.
    openvdb::initialize();
    auto density = openvdb::FloatGrid::create(0.0f);
    density->setName("density");
    density->tree().setValueOn(openvdb::Coord(1, 2, 3), 0.25f);
    const std::string foreign = (scratch.path / "foreign.vdb").string();
    openvdb::io::File(foreign).write({density});
    const VdbSummary f = inspectVdb(foreign);
    CHECK_FALSE(f.hasOrientation);
    CHECK(f.voxels.activeVoxels == 1);
    CHECK(f.voxels.histogram[2] == 1);

    // Not a .vdb: one line naming it, exit 1.
    const std::string text = (scratch.path / "not.vdb").string();
    std::ofstream(text) << "hello";
    CHECK_THROWS_AS(inspectVdb(text), Error);
    const test::RunResult r = test::runYarnvox("inspect " + text);
    CHECK(r.exitCode == 1);
    CHECK(r.output.find(text + ": not an OpenVDB file") != std::string::npos);
}

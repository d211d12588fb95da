#include "core/error.h"
#include "cpu/cpu_voxelizer.h"
#include "garment/cross_section.h"
#include "test_helpers.h"
#include "vdb/file_metadata.h"
#include "vdb/vdb_writer.h"

#include <catch2/catch.hpp>
#include <openvdb/openvdb.h>

#include <filesystem>
#include <csignal>
#include <sys/resource.h>
#include <unistd.h>

using namespace yv;

TEST_CASE("The .vdb reads back with the right grids, names, transform and values", "[vdb]") {
    SliceOptions opt;
    opt.radius = 0.2;
    opt.twist = 1.0;
    const SlicePlan plan = planSlices(test::straightYarn({0.5, -0.25, 1}, {1, 0.3, 0.1}, 4), opt);
    const VoxelGrid grid = makeGrid(plan, 64, 0.0);
    const BrickVolume volume = voxelizeCpu(plan, makeFiberCrossSection(), grid, VoxelizeSettings{});
    REQUIRE(volume.activeVoxelCount() > 0);

    const std::string path = (yv::test::processScratchDir("yv_vdb_output_test") / "output.vdb").string();
    VolumeMetadata meta;
    meta.input = "straight";
    meta.backend = "cpu";
    meta.resolution = 64;
    meta.sliceCount = plan.sliceCount;
    writeVdb(path, volume, meta);
    CHECK_FALSE(std::filesystem::exists(path + ".partial"));

    openvdb::initialize();
    openvdb::io::File file(path);
    file.open();
    auto fileMeta = file.getMetadata();
    // The run's description reads back through the one reader of it.
    CHECK(metadataFields(vdbRunMetadata(*fileMeta, path)) == metadataFields(meta));
    CHECK(fileMeta->metaValue<std::string>("reduce") == "mean");
    CHECK(fileMeta->metaValue<std::int64_t>("slice_count") == std::int64_t(plan.sliceCount));
    CHECK(fileMeta->metaValue<std::int32_t>("resolution") == 64);
    auto density = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("density"));
    auto orientation = openvdb::gridPtrCast<openvdb::Vec3SGrid>(file.readGrid("orientation"));
    file.close();
    REQUIRE(density);
    REQUIRE(orientation);
    CHECK(density->getGridClass() == openvdb::GRID_FOG_VOLUME);
    CHECK(density->activeVoxelCount() == volume.activeVoxelCount());
    CHECK(orientation->activeVoxelCount() == volume.activeVoxelCount());
    CHECK(density->transform() == orientation->transform());
    CHECK(density->voxelSize()[0] == Approx(grid.voxelSize));

    // Voxel (i, j, k) of the grid has its centre at origin + (i + 0.5) h.
    const openvdb::Vec3d centre = density->indexToWorld(openvdb::Coord(3, 4, 5));
    CHECK(centre[0] == Approx(grid.origin.x + 3.5 * grid.voxelSize));
    CHECK(centre[2] == Approx(grid.origin.z + 5.5 * grid.voxelSize));

    double sum = 0.0;
    for (auto it = density->cbeginValueOn(); it; ++it) sum += *it;
    CHECK(sum * std::pow(grid.voxelSize, 3) == Approx(volume.totalMass()).epsilon(1e-9));
    auto acc = orientation->getConstAccessor();
    const VoxelBrick& b = volume.bricks.front();
    const glm::ivec3 o = brickCoord(b.key) * 8;
    for (int v = 0; v < kBrickVoxels; ++v)
        if (b.isActive(v)) {
            const openvdb::Vec3s got = acc.getValue(openvdb::Coord(o.x + (v >> 6), o.y + ((v >> 3) & 7), o.z + (v & 7)));
            CHECK(got[0] == b.orientation[v].x);
            CHECK(got[2] == b.orientation[v].z);
        }
    std::filesystem::remove(path);
}

TEST_CASE("A write that fails leaves nothing behind", "[vdb]") {
    BrickVolume empty;
    empty.grid.dims = {8, 8, 8};
    CHECK_THROWS_AS(writeVdb("/nonexistent-dir/out.vdb", empty, VolumeMetadata{}), Error);

    // A write that fails half-way, in a directory that exists: a 64 KiB
    // file-size limit (SIGXFSZ ignored, so writes past it fail with EFBIG as
    // they fail with ENOSPC on a full disk). Nothing may be left: no output,
    // no temporary file.
    SliceOptions opt;
    opt.radius = 0.2;
    const SlicePlan plan = planSlices(test::straightYarn({0.5, -0.25, 1}, {1, 0.3, 0.1}, 4), opt);
    const BrickVolume volume = voxelizeCpu(plan, makeFiberCrossSection(), makeGrid(plan, 128, 0.0), VoxelizeSettings{});
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("yv_test_fail_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "out.vdb").string();
    struct rlimit previous {};
    REQUIRE(getrlimit(RLIMIT_FSIZE, &previous) == 0);
    const auto previousHandler = std::signal(SIGXFSZ, SIG_IGN);
    struct rlimit limit = previous;
    limit.rlim_cur = 64 * 1024;
    REQUIRE(setrlimit(RLIMIT_FSIZE, &limit) == 0);
    bool threw = false;
    try {
        writeVdb(path, volume, VolumeMetadata{});
    } catch (const Error& e) {
        threw = std::string(e.what()).find("cannot write the OpenVDB file") != std::string::npos;
    }
    setrlimit(RLIMIT_FSIZE, &previous);
    std::signal(SIGXFSZ, previousHandler);
    CHECK(threw);
    CHECK(std::filesystem::is_empty(dir)); // neither out.vdb nor out.vdb.partial-*
    std::filesystem::remove_all(dir);
}

TEST_CASE("Every .vdb compression reads back through OpenVDB with the same values and topology", "[vdb]") {
    SliceOptions opt;
    opt.radius = 0.2;
    const SlicePlan plan = planSlices(test::straightYarn({0.5, -0.25, 1}, {1, 0.3, 0.1}, 4), opt);
    const VoxelGrid grid = makeGrid(plan, 64, 0.0);
    const BrickVolume volume = voxelizeCpu(plan, makeFiberCrossSection(), grid, VoxelizeSettings{});
    REQUIRE(volume.activeVoxelCount() > 100);
    openvdb::initialize();
    const std::string path = (yv::test::processScratchDir("yv_vdb_output_test") / "compression.vdb").string();
    openvdb::FloatGrid::Ptr reference;
    for (VdbCompression c : {VdbCompression::Blosc, VdbCompression::Zip, VdbCompression::ActiveMask, VdbCompression::None}) {
        INFO(toString(c));
        CHECK(parseVdbCompression(toString(c)) == c);
        VdbWriteTimings timings;
        VdbWriteOptions options;
        options.compression = c;
        options.timings = &timings;
        writeVdb(path, volume, VolumeMetadata{}, options);
        CHECK(timings.writeSeconds > 0.0);
        openvdb::io::File file(path);
        file.open();
        auto density = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("density"));
        file.close();
        REQUIRE(density);
        CHECK(density->activeVoxelCount() == volume.activeVoxelCount());
        if (!reference) {
            reference = density;
            continue;
        }
        std::uint64_t differing = 0;
        for (auto it = reference->cbeginValueOn(); it; ++it)
            differing += !density->tree().isValueOn(it.getCoord()) || density->tree().getValue(it.getCoord()) != *it;
        CHECK(differing == 0);
    }
    CHECK_THROWS_AS(parseVdbCompression("lz4"), Error);
}

TEST_CASE("A .vdb's run description: missing fields keep their defaults, a field of another type is refused by name", "[vdb]") {
    openvdb::MetaMap meta;
    meta.insertMeta("input", openvdb::StringMetadata("g.bcc"));
    meta.insertMeta("yarn_radius", openvdb::DoubleMetadata(0.25));
    meta.insertMeta("voxel_size", openvdb::DoubleMetadata(0.5)); // the writer's own: not the run's
    meta.insertMeta("albedo", openvdb::StringMetadata("linear RGB, density-weighted mean"));
    const VolumeMetadata m = vdbRunMetadata(meta, "old.vdb");
    CHECK(m.input == "g.bcc");
    CHECK(m.yarnRadius == 0.25);
    CHECK(m.albedo);
    CHECK(m.supersample == 1);
    CHECK(m.slicesPerSegment == 0);
    meta.insertMeta("resolution", openvdb::StringMetadata("64"));
    CHECK_THROWS_WITH(vdbRunMetadata(meta, "odd.vdb"), Catch::StartsWith("odd.vdb: \"resolution\": expected an integer"));
}

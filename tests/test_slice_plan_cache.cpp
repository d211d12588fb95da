// The slice plan cache of a run's first stage (src/pipeline/sliced_garment.h):
// runs that share one give the voxels a run without it gives, read their
// garment once while the file stays the same, and read it again once it
// changes on disk.
#include "bbox_runs.h"
#include "pipeline/sliced_garment.h"
#include "pipeline/voxelize_run.h"
#include "view/view_volume.h"
#include "run_cli.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <memory>
#include <string>

namespace fs = std::filesystem;

namespace {

yv::VoxelizeJob jobFor(const fs::path& garment, const fs::path& output, std::shared_ptr<yv::SlicePlanCache> cache) {
    yv::VoxelizeJob job;
    job.input = garment.string();
    job.output = output.string();
    job.resolution = 48;
    job.quiet = true;
    job.sliceCache = std::move(cache);
    return job;
}

} // namespace

TEST_CASE("Slice plan cache: runs that share it read the garment once and give the voxels of runs without it, "
          "and a garment changed on disk is read again",
          "[pipeline][cache]") {
    const yv::test::ScratchDir dir{"yv_plan_cache"};
    const fs::path garment = dir.path / "plain.bcc";
    REQUIRE(yv::test::runYarnvox("gen --pattern plain --crossings 16 --quiet -o " + garment.string()).exitCode == 0);
    const auto quiet = [](const std::string&) {};
    const auto cache = std::make_shared<yv::SlicePlanCache>();

    yv::runVoxelize(jobFor(garment, dir.path / "plain.vdb", nullptr), quiet);
    yv::runVoxelize(jobFor(garment, dir.path / "first.vdb", cache), quiet);
    const yv::SlicePlanCache::FileKey key = yv::SlicePlanCache::keyOf(garment.string());
    const std::shared_ptr<const yv::Garment> read = cache->garment(key);
    REQUIRE(read);
    // A second run takes the garment (and its plan) from the cache: the same object, the same voxels.
    yv::VoxelizeJob again = jobFor(garment, dir.path / "second.vdb", cache);
    again.box = yv::parseBoxRequest(false, "0,0,0,24,64,64");
    yv::runVoxelize(again, quiet);
    CHECK(cache->garment(key) == read);
    const yv::test::BoxTestVoxels plain = yv::test::readActiveVoxels(dir.path / "plain.vdb");
    CHECK(plain.size() > 100);
    CHECK(yv::test::readActiveVoxels(dir.path / "first.vdb") == plain);
    yv::VoxelizeJob boxWithout = jobFor(garment, dir.path / "box.vdb", nullptr);
    boxWithout.box = again.box;
    yv::runVoxelize(boxWithout, quiet);
    CHECK(yv::test::readActiveVoxels(dir.path / "second.vdb") == yv::test::readActiveVoxels(dir.path / "box.vdb"));

    // Another garment written over the file: read again, its own voxels.
    REQUIRE(yv::test::runYarnvox("gen --pattern twill --crossings 24 --quiet -o " + garment.string()).exitCode == 0);
    fs::last_write_time(garment, fs::last_write_time(garment) + std::chrono::seconds(2)); // a clock too coarse to tell
    const yv::SlicePlanCache::FileKey changed = yv::SlicePlanCache::keyOf(garment.string());
    CHECK(!(changed == key));
    yv::runVoxelize(jobFor(garment, dir.path / "changed.vdb", cache), quiet);
    yv::runVoxelize(jobFor(garment, dir.path / "changed-plain.vdb", nullptr), quiet);
    CHECK(cache->garment(changed) != read);
    CHECK(cache->garment(key) == nullptr);
    const yv::test::BoxTestVoxels twill = yv::test::readActiveVoxels(dir.path / "changed-plain.vdb");
    CHECK(!(twill == plain));
    CHECK(yv::test::readActiveVoxels(dir.path / "changed.vdb") == twill);
}

TEST_CASE("Slice plan cache: a garment's view keeps what its first voxelization read and planned for its later runs",
          "[view][cache]") {
    const yv::test::ScratchDir dir{"yv_view_plan_cache"};
    const fs::path garment = dir.path / "plain.bcc";
    REQUIRE(yv::test::runYarnvox("gen --pattern plain --crossings 16 --quiet -o " + garment.string()).exitCode == 0);
    yv::VoxelizeJob job;
    job.resolution = 48;
    job.slicesPerSegment = 6; // a plan that does not depend on the voxel size, as at the paper's 50
    job.backend = yv::BackendRequest::Cpu;
    const yv::ViewVolume volume = yv::openViewVolume(garment.string(), job, [](const std::string&) {});
    REQUIRE(volume.voxelizeJob);
    const std::shared_ptr<yv::SlicePlanCache> cache = volume.voxelizeJob->sliceCache;
    REQUIRE(cache);
    const yv::SlicePlanCache::FileKey key = yv::SlicePlanCache::keyOf(garment.string());
    CHECK(cache->garment(key) != nullptr);
    // The plan a view's run asks for (its options worked out apart, with a cache of its own) is there already.
    yv::VoxelizeJob apart = *volume.voxelizeJob;
    apart.sliceCache = std::make_shared<yv::SlicePlanCache>();
    apart.output = (dir.path / "apart.vdb").string();
    yv::StageTimer timer;
    const yv::SlicedGarment sliced = yv::sliceGarment(apart, false, [](const std::string&) {}, timer);
    CHECK(cache->plan(key, sliced.sliceOptions) != nullptr);
}

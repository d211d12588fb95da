// The CPU backend splits each region's slices over TBB's threads, and samples
// only the slices and pixels that can reach the region: neither the thread
// count nor the regions may change a bit of the output.
#include "cpu/cpu_region_backend.h"
#include "cpu/cpu_voxelizer.h"
#include "cpu/slice_sampler.h"
#include "garment/cross_section.h"
#include "garment/generate.h"
#include "plan/zoom_plan.h"
#include "run_cli.h"
#include "test_helpers.h"
#include "vdb_bytes.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <cstring>
#include <fstream>
#include <thread>

using namespace yv;

namespace {

/// Resolves each region's accumulators as they come; every brick must lie
/// in the region that produced it, and regions come in plan order.
class CollectingSink : public RegionSink {
  public:
    void consume(const ZoomRegion&, PackedBricks&&) override { FAIL("the CPU backend hands over accumulators"); }
    void consumeAccumulators(const ZoomRegion& region, std::vector<BrickAccumulator>&& accumulators) override {
        inOrder = inOrder && (regions == 0 || region.id > lastId);
        lastId = region.id;
        ++regions;
        for (const BrickAccumulator& a : accumulators) {
            const glm::ivec3 corner = brickCoord(a.key) * 8;
            inside = inside && glm::all(glm::greaterThanEqual(corner, region.min)) &&
                     glm::all(glm::lessThanEqual(corner + 8, region.max));
            VoxelBrick b;
            if (resolveBrick(Reduce::Mean, Overlap::Clamp, a, b, nullptr)) bricks.push_back(b);
        }
    }
    std::vector<VoxelBrick> bricks;
    bool inside = true, inOrder = true;
    std::uint64_t lastId = 0, regions = 0;
};

/// Bricks that differ in key, mask, any density's bits or any orientation's bits.
std::size_t brickMismatches(std::vector<VoxelBrick> a, std::vector<VoxelBrick> b) {
    const auto byKey = [](const VoxelBrick& x, const VoxelBrick& y) { return x.key < y.key; };
    std::sort(a.begin(), a.end(), byKey);
    std::sort(b.begin(), b.end(), byKey);
    if (a.size() != b.size()) return std::max(a.size(), b.size());
    std::size_t mismatches = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
        mismatches += a[i].key != b[i].key || a[i].activeMask != b[i].activeMask ||
                      std::memcmp(a[i].density.data(), b[i].density.data(), sizeof(float) * kBrickVoxels) != 0 ||
                      std::memcmp(a[i].orientation.data(), b[i].orientation.data(), sizeof(glm::vec3) * kBrickVoxels) != 0;
    return mismatches;
}

} // namespace

TEST_CASE("CPU backend: the same bits from 1 and 4 threads, in few regions and in many", "[cpu][threads]") {
    const test::GeneratedRun run = test::generatedRun(WeavePattern::Plain, GarmentShape::Cylinder, 120, 1.0, 160);
    VoxelizeSettings settings;
    settings.quiet = true;
    // Whether TBB's workers wake before the calling thread has taken every
    // task is the scheduler's: on a loaded 2-core machine one run of a few
    // milliseconds may end on the calling thread alone. So each run must
    // offer every thread tasks, and the runs asked for 4 threads together
    // must have run on at least 2 (a backend that kept to one thread would
    // fail both).
    std::uint64_t mostThreadsRan = 0;
    for (const CrossSection& xs : {makeDiskCrossSection(), makeFiberCrossSection()}) {
        std::vector<VoxelBrick> reference;
        for (std::uint64_t budget : {std::uint64_t(0), std::uint64_t(15000)}) {
            for (int threads : {1, 4}) {
                // global_control lifts TBB's limit past the core count, so 4 threads run on 2 cores.
                tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
                tbb::task_arena arena(threads);
                CpuRegionBackend backend(run.plan, xs, run.grid, settings, budget);
                const ZoomPlan zoom =
                    planZoomRegions(run.plan, run.grid, xs, {backend.fragmentBudget(), backend.maxRegionSize(), 1});
                CollectingSink sink;
                arena.execute([&] { backend.run(zoom.regions, sink); });
                const CpuVoxelizeCounters& c = backend.counters().sampling;
                INFO(xs.name << ", budget " << budget << ": " << zoom.regions.size() << " regions, " << threads
                             << " threads asked, " << c.threads << " ran, " << c.tasks << " tasks, " << c.slicesSampled
                             << " slices sampled of " << run.plan.sliceCount);
                if (budget) CHECK(zoom.regions.size() >= 32);
                CHECK(sink.inside);
                CHECK(sink.inOrder);
                CHECK(sink.regions == zoom.regions.size());
                REQUIRE(sink.bricks.size() > 500);
                CHECK(c.slicesSampled >= run.plan.sliceCount);
                CHECK(c.tasks >= 2 * std::uint64_t(threads));
                if (threads == 1) CHECK(c.threads == 1);
                else mostThreadsRan = std::max(mostThreadsRan, std::uint64_t(c.threads));
                if (reference.empty()) reference = sink.bricks;
                else CHECK(brickMismatches(sink.bricks, reference) == 0);
            }
        }
    }
    CHECK(mostThreadsRan >= 2);
}

TEST_CASE("CPU backend: small regions several at a time, regions as large as the budget one at a time", "[cpu][threads]") {
    const test::GeneratedRun run = test::generatedRun(WeavePattern::Plain, GarmentShape::Cylinder, 120, 1.0, 160);
    VoxelizeSettings settings;
    settings.quiet = true;
    const CrossSection xs = makeDiskCrossSection();
    CpuRegionBackend small(run.plan, xs, run.grid, settings, 15000);
    const ZoomPlan many = planZoomRegions(run.plan, run.grid, xs, {small.fragmentBudget(), small.maxRegionSize(), 1});
    REQUIRE(many.regions.size() >= 32);
    CHECK(small.regionsInFlight(many.regions) == CpuRegionBackend::kMaxRegionsInFlight);
    // A region estimated at the whole memory budget: alone.
    std::vector<ZoomRegion> large = many.regions;
    large[3].estimatedFragments = 1e12;
    CHECK(small.regionsInFlight(large) == 1);
}

TEST_CASE("A sample window keeps exactly the samples of its voxels, in the same order", "[cpu][sampling]") {
    // Windows cut across the slices on every axis, on pixel rows that are
    // not voxel rows (supersample 2), and reach past the grid's faces.
    const test::GeneratedRun run = test::generatedRun(WeavePattern::Knit, GarmentShape::Cylinder, 60, 1.0, 96);
    const VoxelGrid& grid = run.grid;
    for (const CrossSection& xs : {makeDiskCrossSection(), makeFiberCrossSection()}) {
        const double support = textureSupport(xs);
        for (int supersample : {1, 2}) {
            std::size_t total = 0, kept = 0, mismatches = 0;
            for (std::size_t s = 0; s < run.plan.segments.size(); s += 5) {
                const SegmentRecord& seg = run.plan.segments[s];
                for (std::uint32_t k = 0; k < seg.sliceCount; k += 3) {
                    const Slice slice = placeSlice(seg, k);
                    std::vector<SliceSample> all;
                    sampleSlice(slice, run.radius, xs, support, grid, supersample, [&](const SliceSample& x) { all.push_back(x); });
                    total += all.size();
                    if (all.empty()) continue;
                    // A window through the middle of the slice's samples, and its complement's corner.
                    const glm::ivec3 mid = all[all.size() / 2].voxel;
                    for (const auto& [lo, hi] : {std::pair{mid - 1, mid + 2}, std::pair{glm::ivec3(0), mid},
                                                 std::pair{mid, grid.dims + 5}, std::pair{glm::ivec3(-4), glm::ivec3(3, 400, 400)}}) {
                        SampleWindow window;
                        window.min = lo, window.max = hi;
                        std::vector<SliceSample> want, got;
                        for (const SliceSample& x : all)
                            if (glm::all(glm::greaterThanEqual(x.voxel, lo)) && glm::all(glm::lessThan(x.voxel, hi))) want.push_back(x);
                        sampleSlice(slice, run.radius, xs, support, grid, supersample, window, [&](const SliceSample& x) { got.push_back(x); });
                        kept += want.size();
                        if (got.size() != want.size()) {
                            ++mismatches;
                            continue;
                        }
                        for (std::size_t i = 0; i < got.size(); ++i)
                            mismatches += got[i].voxel != want[i].voxel || got[i].volumeFraction != want[i].volumeFraction ||
                                          got[i].density != want[i].density || got[i].direction != want[i].direction;
                    }
                }
            }
            INFO(xs.name << ", supersample " << supersample << ": " << total << " samples, " << kept << " in windows");
            CHECK(total > 5000);
            CHECK(kept > 1000);
            CHECK(mismatches == 0);
        }
    }
}

TEST_CASE("yarnvox voxelize --backend cpu writes the same bytes on one core as on all", "[cpu][threads][cli]") {
    REQUIRE(std::thread::hardware_concurrency() >= 2); // the comparison needs a second core
    test::ScratchDir scratch("yv_cpu_cores");
    const std::string bcc = (scratch.path / "g.bcc").string();
    REQUIRE(test::runYarnvox("gen --pattern plain --shape cylinder --crossings 80 --seed 3 --quiet -o " + bcc).exitCode == 0);
    std::vector<std::uint8_t> first;
    // The run on all cores is repeated (at most five times) until a second
    // thread took part in it: on a loaded 2-core machine TBB may leave a
    // small run to one thread, a run that says nothing about the threads.
    for (const std::string cores : {"taskset -c 0 ", "", "", "", "", ""}) {
        const std::string vdb = (scratch.path / "g.vdb").string(), stats = (scratch.path / "s.json").string();
        const auto r = test::runShell(cores + std::string(YV_BINARY_DIR) + "/yarnvox voxelize " + bcc + " -o " + vdb +
                                      " --backend cpu --cross-section disk --resolution 160 --fragment-budget 20000 --quiet --stats " +
                                      stats);
        INFO(cores << r.output);
        REQUIRE(r.exitCode == 0);
        std::ifstream in(stats);
        const nlohmann::json backend = nlohmann::json::parse(in)["backend_stats"];
        CHECK(backend["zoom_regions"].get<int>() >= 16);
        const int threads = backend["threads"].get<int>();
        if (!cores.empty()) CHECK(threads == 1);
        const std::vector<std::uint8_t> bytes = test::vdbBytesWithoutUuid(vdb);
        const bool sameBytes = first.empty() || bytes == first; // not CHECKed directly: megabytes to print
        CHECK(sameBytes);
        if (first.empty()) first = bytes;
        else if (threads >= 2) return;
    }
    FAIL("five runs on all cores each sampled on one thread: the comparison was never made across threads");
}

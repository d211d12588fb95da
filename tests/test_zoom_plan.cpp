// The zoom plan's split: a flat garment's thickness is never halved, a round
// one is split on every axis, a run has enough regions for the writer to
// keep up with the GPU, a coarse grid's estimate is not rounded away, and a
// plan told to stop (a run given up) gives up.
#include "garment/cross_section.h"
#include "plan/zoom_plan.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <set>

using namespace yv;

namespace {

ZoomPlan planOf(const test::GeneratedRun& run, std::uint64_t budget) {
    return planZoomRegions(run.plan, run.grid, makeFiberCrossSection(), {budget, 1024, 1});
}

/// The fragments the plan expects of the whole garment.
double expectedFragments(const test::GeneratedRun& run) { return planOf(run, std::uint64_t(1) << 40).estimatedFragments; }

} // namespace

TEST_CASE("Zoom plan: a flat garment's regions keep its whole thickness", "[plan]") {
    const test::GeneratedRun run = test::generatedRun(WeavePattern::Plain, GarmentShape::Flat, 4000, 1.0, 1024);
    const glm::ivec3 dims = run.grid.dims;
    const int thin = std::min({dims.x, dims.y, dims.z});
    const int thinAxis = dims.x == thin ? 0 : (dims.y == thin ? 1 : 2);
    INFO("grid " << dims.x << " x " << dims.y << " x " << dims.z);
    REQUIRE(thin <= 128);
    REQUIRE(4 * thin <= std::max({dims.x, dims.y, dims.z}));
    // A budget far below the garment's: many regions.
    const ZoomPlan zoom = planOf(run, std::uint64_t(expectedFragments(run) / 64) + 1);
    REQUIRE(zoom.regions.size() >= 8);
    for (const ZoomRegion& r : zoom.regions) {
        CHECK(r.min[thinAxis] == 0);
        CHECK(r.max[thinAxis] == dims[thinAxis]);
    }
}

TEST_CASE("Zoom plan: a round garment is split on every axis", "[plan]") {
    const test::GeneratedRun run = test::generatedRun(WeavePattern::Twill, GarmentShape::Cylinder, 4000, 1.0, 512);
    const ZoomPlan zoom = planOf(run, std::uint64_t(expectedFragments(run) / 64) + 1);
    REQUIRE(zoom.regions.size() >= 8);
    for (int a = 0; a < 3; ++a) {
        INFO("axis " << a);
        CHECK(std::any_of(zoom.regions.begin(), zoom.regions.end(),
                          [&](const ZoomRegion& r) { return r.max[a] - r.min[a] < run.grid.dims[a]; }));
    }
}

TEST_CASE("Zoom plan: with a budget far above the garment, regions stay within a 32nd of it", "[plan]") {
    const test::GeneratedRun run = test::generatedRun(WeavePattern::Twill, GarmentShape::Cylinder, 20000, 1.0, 2048);
    const double total = expectedFragments(run);
    INFO("expected fragments " << total);
    REQUIRE(total > 8.0 * (1 << 20));
    // The budget alone would keep it whole (but for the 1024-voxel region cap).
    const ZoomPlan zoom = planOf(run, std::uint64_t(1) << 40);
    CHECK(zoom.regions.size() >= 8);
    const double target = std::max(double(1 << 20), total / 32.0);
    for (const ZoomRegion& r : zoom.regions) {
        const glm::ivec3 size = r.max - r.min;
        if (size.x > 8 || size.y > 8 || size.z > 8) CHECK(r.estimatedFragments <= target);
    }
}

TEST_CASE("Zoom plan: fewer pipeline regions cut a large garment into fewer and hotter regions", "[plan]") {
    const test::GeneratedRun run = test::generatedRun(WeavePattern::Twill, GarmentShape::Cylinder, 20000, 1.0, 2048);
    const auto planWith = [&](double regions) {
        return planZoomRegions(run.plan, run.grid, makeFiberCrossSection(), {std::uint64_t(1) << 40, 1024, 1, nullptr, regions});
    };
    const ZoomPlan many = planWith(kPipelineRegions), few = planWith(2.0);
    const double total = many.estimatedFragments;
    INFO("expected fragments " << total << ": " << many.regions.size() << " regions at 32, " << few.regions.size() << " at 2");
    REQUIRE(total > 8.0 * (1 << 20));
    CHECK(few.regions.size() < many.regions.size());
    CHECK(few.regions.size() >= 2);
    // Each region within half the garment (but a brick-sized one), and some above a 32nd.
    bool aboveThirtySecond = false;
    for (const ZoomRegion& r : few.regions) {
        const glm::ivec3 size = r.max - r.min;
        if (size.x > 8 || size.y > 8 || size.z > 8) CHECK(r.estimatedFragments <= total / 2.0);
        aboveThirtySecond = aboveThirtySecond || r.estimatedFragments > total / 32.0;
    }
    CHECK(aboveThirtySecond);
    // The same voxels reached: the regions of either plan hold every segment of the other's.
    std::set<std::uint32_t> inMany, inFew;
    for (const ZoomRegion& r : many.regions) inMany.insert(r.segments.begin(), r.segments.end());
    for (const ZoomRegion& r : few.regions) inFew.insert(r.segments.begin(), r.segments.end());
    CHECK(inMany == inFew);
    CHECK_THROWS_WITH(planWith(0.5), Catch::Contains("at least one region"));
}

TEST_CASE("Zoom plan: a coarse grid's estimate keeps its fractions of a fragment", "[plan]") {
    // At 64 a slice of this garment expects well under one fragment.
    const test::GeneratedRun coarse = test::generatedRun(WeavePattern::Plain, GarmentShape::Flat, 4000, 1.0, 64);
    const test::GeneratedRun fine = test::generatedRun(WeavePattern::Plain, GarmentShape::Flat, 4000, 1.0, 128);
    const double a = expectedFragments(coarse), b = expectedFragments(fine);
    INFO("at 64: " << a << " for " << coarse.plan.sliceCount << " slices; at 128: " << b);
    REQUIRE(a > 0.0);
    CHECK(a < 0.5 * double(coarse.plan.sliceCount));
    // Twice the resolution: each slice's square four times the pixels, and
    // twice the slices.
    CHECK(b / a > 4.0);
    CHECK(b / a < 12.0);
}

TEST_CASE("Zoom plan: a plan told to stop gives up with no regions, and one whose stop stays unset plans as without it",
          "[plan][cancel]") {
    const test::GeneratedRun run = test::generatedRun(WeavePattern::Twill, GarmentShape::Cylinder, 4000, 1.0, 512);
    const std::uint64_t budget = std::uint64_t(expectedFragments(run) / 64) + 1;
    const ZoomPlan plain = planOf(run, budget);
    REQUIRE(plain.regions.size() >= 8);
    CHECK_FALSE(plain.givenUp);

    std::atomic<bool> stop(false);
    const ZoomPlan kept = planZoomRegions(run.plan, run.grid, makeFiberCrossSection(), {budget, 1024, 1, &stop});
    CHECK_FALSE(kept.givenUp);
    REQUIRE(kept.regions.size() == plain.regions.size());
    for (std::size_t i = 0; i < kept.regions.size(); ++i) {
        CHECK(kept.regions[i].min == plain.regions[i].min);
        CHECK(kept.regions[i].max == plain.regions[i].max);
        CHECK(kept.regions[i].segments == plain.regions[i].segments);
    }

    stop = true;
    const ZoomPlan stopped = planZoomRegions(run.plan, run.grid, makeFiberCrossSection(), {budget, 1024, 1, &stop});
    CHECK(stopped.givenUp);
    CHECK(stopped.regions.empty());
}

// What the camera sees, for voxelize-on-stop: the seen box is the bounds of
// exactly the voxels in view (checked against points sampled through the
// box), the run's voxel size is a pixel at the point looked at within its
// budgets, its texts read back to its numbers, and a camera mapped onto a
// finer grid draws every point where the first camera drew it.
#include "view/view_camera.h"
#include "view/view_region.h"

#include <catch2/catch.hpp>

#include <glm/common.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>

using namespace yv;

namespace {

/// Clip coordinates of `p` under `camera`.
glm::dvec4 clipOf(const Camera& camera, const glm::dvec3& p) { return camera.viewProjection() * glm::dvec4(p, 1.0); }

/// The bounds of the points of a fine lattice through `box` that `camera` sees.
/// Clip coordinates are affine in the lattice indices, so they are stepped by
/// plain additions: the 64 M points of a 400-step lattice take seconds under
/// the sanitizers too, where a matrix product a point took minutes.
RealBox sampledSeenBox(const VoxelBox& box, const Camera& camera, int steps) {
    RealBox seen{glm::dvec3(1e300), glm::dvec3(-1e300)};
    const glm::dvec3 lo(box.min), size(box.dims());
    const glm::dmat4 m = camera.viewProjection();
    const glm::dvec4 origin = m * glm::dvec4(lo, 1.0);
    const glm::dvec4 di = m * glm::dvec4(size.x / steps, 0, 0, 0);
    const glm::dvec4 dj = m * glm::dvec4(0, size.y / steps, 0, 0);
    const glm::dvec4 dk = m * glm::dvec4(0, 0, size.z / steps, 0);
    for (int i = 0; i <= steps; ++i)
        for (int j = 0; j <= steps; ++j) {
            const glm::dvec4 row = origin + double(i) * di + double(j) * dj;
            double x = row.x, y = row.y, w = row.w;
            int first = -1, last = -1;
            for (int k = 0; k <= steps; ++k, x += dk.x, y += dk.y, w += dk.w) {
                if (!(w > 0.0 && std::abs(x) <= w && std::abs(y) <= w)) continue;
                if (first < 0) first = k;
                last = k;
            }
            if (first < 0) continue;
            // The points seen along a lattice line are one run (the pyramid is convex).
            for (const int k : {first, last}) {
                const glm::dvec3 p = lo + size * glm::dvec3(i, j, k) / double(steps);
                seen.min = glm::min(seen.min, p);
                seen.max = glm::max(seen.max, p);
            }
        }
    return seen;
}

std::array<double, 6> numbers(const std::string& text) {
    std::array<double, 6> v{};
    std::stringstream in(text);
    for (double& x : v) {
        std::string word;
        REQUIRE(std::getline(in, word, ','));
        x = std::strtod(word.c_str(), nullptr);
    }
    return v;
}

const VoxelBox kBox{{0, 0, 0}, {256, 128, 64}};

} // namespace

TEST_CASE("Seen box: a camera far enough away sees the whole box, a close one the part its pyramid holds", "[view][region]") {
    const Camera far = viewCamera(kBox, ViewCamera{30, 20, 4}, 320, 180);
    const RealBox whole = seenBox(kBox, far);
    CHECK(whole.min == glm::dvec3(kBox.min));
    CHECK(whole.max == glm::dvec3(kBox.max));

    for (const ViewCamera& view : {ViewCamera{30, 20, 0.6}, ViewCamera{120, 45, 0.4, 0.3, -0.2}, ViewCamera{0, 89, 0.3}}) {
        const Camera close = viewCamera(kBox, view, 320, 180);
        const RealBox seen = seenBox(kBox, close);
        const RealBox sampled = sampledSeenBox(kBox, close, 400);
        INFO(view.azimuth << " " << view.elevation << " " << view.distance);
        REQUIRE(!seen.empty());
        // Every point seen is inside, and the box is no larger than the lattice
        // allows (two steps: a thin sliver of the pyramid can pass between its points).
        const glm::dvec3 step = glm::dvec3(kBox.dims()) / 400.0;
        CHECK(seen.contains(sampled));
        for (int a = 0; a < 3; ++a) {
            CHECK(seen.min[a] >= sampled.min[a] - 2 * step[a]);
            CHECK(seen.max[a] <= sampled.max[a] + 2 * step[a]);
        }
        // A close camera sees less than the whole box.
        CHECK(!seen.contains(whole));
    }
    // Looking away from the box: nothing.
    Camera away = far;
    away.eye = glm::dvec3(-1000, 64, 32);
    away.view = glm::lookAt(away.eye, glm::dvec3(-2000, 64, 32), glm::dvec3(0, 0, 1));
    CHECK(seenBox(kBox, away).empty());
}

TEST_CASE("View voxelization: a voxel a pixel at the point looked at, within the budgets, and texts that read back",
          "[view][region]") {
    VoxelGrid grid;
    grid.origin = {-1.25, 2.5, 0.125};
    grid.voxelSize = 0.01;
    grid.dims = {kBox.max.x, kBox.max.y, kBox.max.z};
    std::string why;
    // The whole garment in view at about a voxel a pixel: nothing to add.
    CHECK(!planViewVoxelization(kBox, grid, viewCamera(kBox, ViewCamera{30, 20, 4}, 320, 180), 1024, 32768, why));
    CHECK(why.find("no finer than the volume's voxels") != std::string::npos);

    const Camera close = viewCamera(kBox, ViewCamera{30, 20, 0.5}, 640, 360);
    const auto run = planViewVoxelization(kBox, grid, close, 1024, 32768, why);
    REQUIRE(run);
    // The texts are the numbers.
    CHECK(std::strtod(run->voxelSizeText.c_str(), nullptr) == run->voxelSize);
    const std::array<double, 6> box = numbers(run->boxText);
    for (int a = 0; a < 3; ++a) {
        CHECK(box[a] == run->world.min[a]);
        CHECK(box[3 + a] == run->world.max[a]);
    }
    // The box holds what is seen, in world units, with half a voxel to spare.
    const RealBox seen = seenBox(kBox, close);
    for (int a = 0; a < 3; ++a) {
        CHECK(run->world.min[a] <= grid.origin[a] + seen.min[a] * grid.voxelSize - 0.5 * run->voxelSize);
        CHECK(run->world.max[a] >= grid.origin[a] + seen.max[a] * grid.voxelSize + 0.5 * run->voxelSize);
        CHECK(run->world.max[a] - run->world.min[a] < (seen.max[a] - seen.min[a]) * grid.voxelSize + 2 * run->voxelSize);
    }
    // A pixel at the seen box's centre, in world units, to three digits,
    // unless 1024 voxels along the box's longest side are coarser; finer than the grid.
    const glm::dvec3 centre = 0.5 * (seen.min + seen.max);
    const glm::dvec3 forward = -glm::dvec3(glm::inverse(close.view)[2]);
    const double depth = glm::dot(centre - close.eye, forward);
    const double pixel = 2.0 * depth * std::tan(glm::radians(kFieldOfViewDegrees) / 2.0) / 360.0 * grid.voxelSize;
    const glm::dvec3 seenSize = seen.max - seen.min;
    const double longest = std::max({seenSize.x, seenSize.y, seenSize.z}) * grid.voxelSize;
    const double expected = std::max(pixel, longest / 1024.0);
    CHECK(run->voxelSize >= expected);
    CHECK(run->voxelSize <= expected * 1.01);
    CHECK(run->voxelSize < grid.voxelSize);
    // Here a pixel is the finer of the two: without the side budget, a voxel a pixel.
    const auto unbudgeted = planViewVoxelization(kBox, grid, close, 8192, 32768, why);
    REQUIRE(unbudgeted);
    CHECK(pixel < longest / 1024.0);
    CHECK(unbudgeted->voxelSize >= pixel);
    CHECK(unbudgeted->voxelSize <= pixel * 1.01);

    // A smaller budget of voxels a side coarsens the voxels to fit it.
    const auto capped = planViewVoxelization(kBox, grid, close, 400, 32768, why);
    REQUIRE(capped);
    const glm::dvec3 size = capped->world.max - capped->world.min;
    CHECK(std::max({size.x, size.y, size.z}) / capped->voxelSize <= 400.0 + 1.0);
    CHECK(capped->voxelSize > run->voxelSize);
    // One so small that the grid's own voxels are finer: nothing to run.
    CHECK(!planViewVoxelization(kBox, grid, close, 64, 32768, why));
    // And a whole-grid cap does too: no finer than the grid's longest side over it.
    const auto wholeCap = planViewVoxelization(kBox, grid, close, 1024, 300, why);
    REQUIRE(wholeCap);
    CHECK(wholeCap->voxelSize >= 256 * grid.voxelSize / 300);
}

TEST_CASE("A camera mapped onto a finer grid draws every point where the first drew it", "[view][region]") {
    const Camera camera = viewCamera(kBox, ViewCamera{75, 30, 0.8, 0.1, 0.2}, 300, 200);
    const double scale = 4.0;
    const glm::dvec3 offset(3.5, -2.0, 12.25);
    const Camera mapped = mapCamera(camera, scale, offset);
    CHECK(mapped.eye == scale * camera.eye + offset);
    for (const glm::dvec3 p : {glm::dvec3(128, 64, 32), glm::dvec3(10, 100, 5), glm::dvec3(200, 20, 60)}) {
        const glm::dvec4 a = clipOf(camera, p), b = clipOf(mapped, scale * p + offset);
        INFO(p.x << " " << p.y << " " << p.z);
        CHECK(b.x / b.w == Approx(a.x / a.w).margin(1e-9));
        CHECK(b.y / b.w == Approx(a.y / a.w).margin(1e-9));
        CHECK(b.z / b.w == Approx(a.z / a.w).margin(1e-9));
    }
}

TEST_CASE("View voxelization: a large run is shown first from a pass with voxels four times as large, a small one is not",
          "[view][region]") {
    ViewVoxelization run;
    run.world = RealBox{{0.0, 0.0, 0.0}, {2.0, 1.0, 0.5}};
    run.boxText = "0,0,0,2,1,0.5";
    run.voxelSize = 0.01; // 200 voxels along the longest side
    run.voxelSizeText = "0.01";
    run.twist = 3.5;
    const std::optional<ViewVoxelization> first = refinePass(run, 0.1);
    REQUIRE(first);
    CHECK(first->firstPass);
    CHECK(!run.firstPass);
    CHECK(first->voxelSizeText == "0.04");
    CHECK(first->voxelSize == std::strtod("0.04", nullptr));
    CHECK(first->boxText == run.boxText);
    CHECK(first->twist == run.twist);
    CHECK(!(*first == run));
    CHECK(!refinePass(*first, 0.1)); // a first pass has none of its own
    // Its voxels no finer than the volume opened: it would show nothing new.
    CHECK(!refinePass(run, 0.04));
    CHECK(refinePass(run, 0.05));
    // Under kRefineFromVoxels along the longest side: one pass.
    run.voxelSize = 2.0 / (kRefineFromVoxels - 1);
    CHECK(!refinePass(run, 1.0));
    run.voxelSize = 2.0 / kRefineFromVoxels;
    CHECK(refinePass(run, 1.0));
}

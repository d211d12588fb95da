#include "plan/grid.h"

#include "core/error.h"
#include "core/world_units.h"

#include <algorithm>
#include <string>

namespace yv {
namespace {

/// The garment box: the curves grown by the slice half-diagonal.
void garmentBox(glm::dvec3 curveMin, glm::dvec3 curveMax, double radius, glm::dvec3& lo, glm::dvec3& hi) {
    const double reach = radius * std::sqrt(2.0);
    lo = curveMin - reach;
    hi = curveMax + reach;
}

/// Voxels a grid may have on one axis: brick keys hold 21 bits per axis of
/// 8-voxel bricks (core/bricks.h), so voxel coordinates stay below 2^24.
constexpr double kMaxAxisVoxels = double(1 << 24);
// shaders/append.frag forms a fragment's global pixel (voxel index times
// --supersample, at most 16) in a 32-bit int before any float: it cannot wrap.
static_assert(kMaxAxisVoxels * 16 < 2147483648.0);

/// Refuses `voxels` on one axis when they do not fit (or are not a number:
/// a NaN must not reach the int conversion).
void checkAxisVoxels(double voxels, double extent, double h) {
    if (!(voxels <= kMaxAxisVoxels))
        throw Error("a garment box " + numberText(extent) + " wide in voxels of " + numberText(h) + " needs " +
                    numberText(voxels) + " voxels on one axis, over the limit of 2^24 = 16777216 "
                    "(brick keys hold 21 bits per axis): give a coarser --voxel-size or --resolution");
}

double voxelSizeForBox(glm::dvec3 lo, glm::dvec3 hi, int resolution, double voxelSize) {
    if ((resolution > 0) == (voxelSize > 0.0))
        throw Error("give exactly one of --resolution (voxels on the longest axis) and --voxel-size");
    const glm::dvec3 extent = hi - lo;
    const double longest = std::max({extent.x, extent.y, extent.z});
    const double h = voxelSize > 0.0 ? voxelSize : longest / resolution;
    // Known before any slice is planned: a voxel size far too small for the
    // garment would otherwise first ask for billions of slices.
    checkAxisVoxels(longest / h, longest, h);
    return h;
}

} // namespace

double voxelSizeFor(const Garment& garment, double radius, int resolution, double voxelSize) {
    glm::dvec3 curveMin, curveMax;
    curveBounds(garment, curveMin, curveMax);
    return voxelSizeForCurves(curveMin, curveMax, radius, resolution, voxelSize);
}

double voxelSizeForCurves(const glm::dvec3& curveMin, const glm::dvec3& curveMax, double radius, int resolution,
                          double voxelSize) {
    glm::dvec3 lo, hi;
    if (!(curveMin.x <= curveMax.x)) throw Error("the garment has no curves: nothing to voxelize");
    garmentBox(curveMin, curveMax, radius, lo, hi);
    return voxelSizeForBox(lo, hi, resolution, voxelSize);
}

VoxelGrid makeGrid(const SlicePlan& plan, int resolution, double voxelSize) {
    if (plan.sliceCount == 0) throw Error("the garment has no slices: nothing to voxelize");
    glm::dvec3 lo, hi;
    garmentBox(plan.curveMin, plan.curveMax, plan.options.radius, lo, hi);
    const glm::dvec3 extent = hi - lo;

    VoxelGrid grid;
    grid.voxelSize = voxelSizeForBox(lo, hi, resolution, voxelSize);
    const double h = grid.voxelSize;
    // Padding on each side: what slabs reach past the slice squares (half a
    // slab's depth along the projection axis), plus kSampleReachVoxels for the
    // pixel footprints around the squares, plus one voxel.
    const double slabReach = std::max(0.0, plan.maxReach - plan.options.radius * std::sqrt(2.0));
    const double padding = 1.0 + kSampleReachVoxels + std::ceil(slabReach / h);
    const glm::dvec3 size = extent / h + 2.0 * padding;
    for (int a = 0; a < 3; ++a) {
        const double n = std::ceil(size[a] / 8.0) * 8.0;
        checkAxisVoxels(n, extent[a], h);
        grid.dims[a] = static_cast<int>(n);
    }
    // Centre the garment in the rounded-up grid.
    grid.origin = lo - 0.5 * (glm::dvec3(grid.dims) * h - extent);
    return grid;
}

} // namespace yv

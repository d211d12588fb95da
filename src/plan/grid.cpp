#include "plan/grid.h"

#include "core/error.h"

#include <algorithm>
#include <string>

namespace yv {

VoxelGrid makeGrid(const SlicePlan& plan, int resolution, double voxelSize) {
    if ((resolution > 0) == (voxelSize > 0.0))
        throw Error("give exactly one of --resolution (voxels on the longest axis) and --voxel-size");
    if (plan.sliceCount == 0) throw Error("the garment has no slices: nothing to voxelize");

    const double reach = plan.options.radius * std::sqrt(2.0);
    const glm::dvec3 lo = plan.centerMin - reach, hi = plan.centerMax + reach;
    const glm::dvec3 extent = hi - lo;
    const double longest = std::max({extent.x, extent.y, extent.z});

    VoxelGrid grid;
    grid.voxelSize = voxelSize > 0.0 ? voxelSize : longest / resolution;
    const double h = grid.voxelSize;
    glm::dvec3 size = extent / h + 2.0; // one voxel of padding on each side
    for (int a = 0; a < 3; ++a) {
        const double n = std::ceil(size[a] / 8.0) * 8.0;
        if (n > double(1 << 24))
            throw Error("grid of " + std::to_string(std::int64_t(n)) + " voxels on one axis exceeds the limit of 2^24");
        grid.dims[a] = static_cast<int>(n);
    }
    // Centre the garment in the rounded-up grid.
    grid.origin = lo - 0.5 * (glm::dvec3(grid.dims) * h - extent);
    return grid;
}

} // namespace yv

// The voxel grid: where voxel (i, j, k) lies in the world. Every layer
// speaks of voxels through it; plan/grid.h chooses one for a garment.
#pragma once

#include <glm/vec3.hpp>

#include <cstdint>

namespace yv {

/// Voxel (i, j, k) covers origin + [i, i+1) * voxelSize (and likewise in j, k);
/// its centre is origin + (i + 0.5) * voxelSize. Dimensions are multiples of
/// 8, so the grid is a whole number of 8^3 bricks.
struct VoxelGrid {
    glm::dvec3 origin{0.0};
    double voxelSize = 1.0;
    glm::ivec3 dims{0};

    std::uint64_t voxelCount() const { return std::uint64_t(dims.x) * dims.y * dims.z; }
    glm::ivec3 brickDims() const { return dims / 8; }
};

} // namespace yv

// A box of voxels of a grid, in voxel indices: what `export --bbox` cuts out,
// what `voxelize --bbox` voxelizes, what `inspect` draws of a volume.
#pragma once

#include <glm/common.hpp>
#include <glm/vec3.hpp>

namespace yv {

/// Voxels in index coordinates, min inclusive, max exclusive (the bounds
/// `yarnvox inspect` prints for a work directory's regions).
struct VoxelBox {
    glm::ivec3 min{0}, max{0};
    glm::ivec3 dims() const { return max - min; }
    bool empty() const { return max.x <= min.x || max.y <= min.y || max.z <= min.z; }
    bool contains(glm::ivec3 v) const {
        return v.x >= min.x && v.y >= min.y && v.z >= min.z && v.x < max.x && v.y < max.y && v.z < max.z;
    }
    bool operator==(const VoxelBox&) const = default;
};

/// The voxels in both boxes (empty() when they do not meet).
inline VoxelBox intersect(const VoxelBox& a, const VoxelBox& b) { return {glm::max(a.min, b.min), glm::min(a.max, b.max)}; }

/// The smallest box of whole 8^3 bricks that holds `b`.
inline VoxelBox roundOutToBricks(const VoxelBox& b) {
    const auto down = [](int v) { return v >= 0 ? v / 8 * 8 : -((-v + 7) / 8 * 8); };
    const auto up = [&](int v) { return -down(-v); };
    return {{down(b.min.x), down(b.min.y), down(b.min.z)}, {up(b.max.x), up(b.max.y), up(b.max.z)}};
}

} // namespace yv

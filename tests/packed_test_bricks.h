// Bricks packed as the GPU's resolve reads them back (core/packed_bricks.h),
// built on the host for tests of what takes packed regions.
#pragma once

#include "core/packed_bricks.h"

#include <cstdint>
#include <vector>

namespace yv::test {

/// `bricks` packed: a header per brick, its active voxels in voxel order,
/// their colours where the bricks carry them. Tallies are left at zero.
inline PackedBricks packBricks(const std::vector<VoxelBrick>& bricks) {
    PackedBricks out;
    for (const VoxelBrick& b : bricks) {
        PackedBrickHeader h{};
        h.key[0] = static_cast<std::uint32_t>(b.key);
        h.key[1] = static_cast<std::uint32_t>(b.key >> 32);
        for (int w = 0; w < kBrickVoxels / 64; ++w) {
            h.activeMask[2 * w] = static_cast<std::uint32_t>(b.activeMask[w]);
            h.activeMask[2 * w + 1] = static_cast<std::uint32_t>(b.activeMask[w] >> 32);
        }
        h.firstVoxel = static_cast<std::uint32_t>(out.voxels.size());
        h.activeCount = static_cast<std::uint32_t>(b.activeCount());
        for (int v = 0; v < kBrickVoxels; ++v) {
            if (!b.isActive(v)) continue;
            out.voxels.push_back({b.density[v], {b.orientation[v].x, b.orientation[v].y, b.orientation[v].z}});
            if (!b.albedo.empty()) out.albedo.push_back({{b.albedo[v].x, b.albedo[v].y, b.albedo[v].z}});
        }
        out.headers.push_back(h);
    }
    return out;
}

} // namespace yv::test

// An 8^3 brick's active voxels as a bit mask: eight 64-bit words, voxel v at
// bit v % 64 of word v / 64 (the order of OpenVDB's leaf masks), as bricks,
// packed bricks, region files and .vdb leaf records all hold it.
#pragma once

#include <bit>
#include <cstdint>
#include <span>

namespace yv {

constexpr int kBrickMaskWords = 8;

/// Active voxels in a brick's mask.
inline int activeVoxelCount(std::span<const std::uint64_t, kBrickMaskWords> mask) {
    int n = 0;
    for (std::uint64_t word : mask) n += std::popcount(word);
    return n;
}

} // namespace yv

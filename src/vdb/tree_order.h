// The order in which OpenVDB's default tree (root, 32^3 and 16^3 internal
// nodes, 8^3 leaves) visits its leaves when it writes them: root children by
// origin (x, then y, then z), then each internal node's children by index,
// x-major. Sorting bricks by this key puts them in the order of a .vdb's
// topology and buffers without building a tree.
#pragma once

#include "core/bricks.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace yv {

/// Leaves per axis under one 16^3 internal node, and 16^3 nodes under one 32^3 node.
constexpr int kLowerNodeBricks = 16;  ///< 128 voxels
constexpr int kUpperNodeBricks = 512; ///< 4096 voxels: one root child

/// Brick coordinates are non-negative and below 2^21 (brickKey), so the
/// root level needs 12 bits per axis, the upper node 5 and the lower node 4.
inline std::uint64_t treeOrderKey(glm::ivec3 b) {
    const auto u = [](int v) { return std::uint64_t(std::uint32_t(v)); };
    const std::uint64_t root = (u(b.x >> 9) << 24) | (u(b.y >> 9) << 12) | u(b.z >> 9);
    const std::uint64_t upper = (u((b.x >> 4) & 31) << 10) | (u((b.y >> 4) & 31) << 5) | u((b.z >> 4) & 31);
    const std::uint64_t lower = (u(b.x & 15) << 8) | (u(b.y & 15) << 4) | u(b.z & 15);
    return (root << 27) | (upper << 12) | lower;
}

/// Brick coordinates of a tree order key (the inverse of treeOrderKey).
inline glm::ivec3 treeOrderCoord(std::uint64_t key) {
    const auto axis = [key](int rootShift, int upperShift, int lowerShift) {
        return int(((key >> rootShift) & 0xfff) << 9 | ((key >> upperShift) & 31) << 4 | ((key >> lowerShift) & 15));
    };
    return {axis(51, 22, 8), axis(39, 17, 4), axis(27, 12, 0)};
}
/// Regions (anything with a voxel box starting at `min`, whole bricks) sorted
/// by the tree order key of their lowest brick, which no brick of the region
/// comes before; returns those keys, in the same order. Leaves before the
/// next unfinished region's key are final (vdb/leaf_stream.h).
template <typename Region> std::vector<std::uint64_t> sortByFirstTreeOrder(std::vector<Region>& regions) {
    const auto firstOrder = [](const Region& r) { return treeOrderKey(r.min / kBrickSize); };
    std::stable_sort(regions.begin(), regions.end(),
                     [&](const Region& a, const Region& b) { return firstOrder(a) < firstOrder(b); });
    std::vector<std::uint64_t> orders;
    orders.reserve(regions.size());
    for (const Region& r : regions) orders.push_back(firstOrder(r));
    return orders;
}

/// The parts of a tree order key: the root child, the upper node's child index, the lower node's child index.
inline std::uint64_t rootChildOfOrder(std::uint64_t key) { return key >> 27; }
inline std::uint64_t lowerNodeOfOrder(std::uint64_t key) { return key >> 12; }
inline unsigned upperIndexOfOrder(std::uint64_t key) { return unsigned((key >> 12) & 0x7fff); }
inline unsigned lowerIndexOfOrder(std::uint64_t key) { return unsigned(key & 0xfff); }

} // namespace yv

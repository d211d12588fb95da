// Sparse 8^3 bricks: the unit every backend accumulates into and every
// output (brick store, OpenVDB) is built from. An 8^3 brick is exactly an
// OpenVDB LeafNode, and voxels inside it are ordered as OpenVDB orders them.
#pragma once

#include "core/brick_mask.h"
#include "core/sampling.h"
#include "core/voxel_grid.h"

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace yv {

constexpr int kBrickSize = 8;
constexpr int kBrickVoxels = 512;

/// Offset of local voxel (x, y, z) in a brick: OpenVDB's LeafNode order.
constexpr int brickOffset(int x, int y, int z) { return (x << 6) | (y << 3) | z; }

/// Packs brick coordinates (voxel coordinates / 8, each below 2^21) into one
/// sortable key: z fastest, so sorted keys follow OpenVDB's traversal order.
inline std::uint64_t brickKey(glm::ivec3 b) {
    return (std::uint64_t(b.x) << 42) | (std::uint64_t(b.y) << 21) | std::uint64_t(b.z);
}
inline glm::ivec3 brickCoord(std::uint64_t key) {
    return {int(key >> 42), int((key >> 21) & 0x1fffff), int(key & 0x1fffff)};
}

/// Accumulator state of one brick: wordsPerVoxel(reduce, albedo) channels of
/// 512 words, channel-major (channel c of voxel v at c * 512 + v), the layout
/// the GL brick passes write.
struct BrickAccumulator {
    std::uint64_t key = 0;
    std::vector<std::uint32_t> words;

    /// Mean words with the three albedo channels after the tensor.
    bool hasAlbedo() const { return words.size() == std::size_t(kMeanWords + kAlbedoWords) * 512; }
};

/// Adds (mean) or maxes (max) `src` into `dst`: associative and commutative,
/// so any split of the work gives the same bits. `albedo`: the mean words
/// carry the albedo channels.
void combineAccumulators(Reduce reduce, std::uint32_t* dst, const std::uint32_t* src, bool albedo = false);

/// Final values of one brick.
struct VoxelBrick {
    std::uint64_t key = 0;
    std::array<float, kBrickVoxels> density{};
    std::array<glm::vec3, kBrickVoxels> orientation{};
    std::array<std::uint64_t, kBrickMaskWords> activeMask{}; ///< voxel v active: bit v % 64 of word v / 64
    /// Linear RGB fibre colour per voxel (zero where inactive), for runs with
    /// --albedo; empty otherwise, so runs without it carry nothing.
    std::vector<glm::vec3> albedo;

    bool isActive(int v) const { return (activeMask[v >> 6] >> (v & 63)) & 1; }
    int activeCount() const;
};

/// Sums of slab shares that tile a voxel exactly still differ from 1 by a few
/// fixed-point units; a voxel counts as over one only past this margin.
constexpr double kOverOneMargin = 1.0 / 1024.0;

/// What resolving found, summed over voxels: how much density the overlap
/// rule clamped away, for --stats and the summary line.
struct ResolveTally {
    std::uint64_t activeVoxels = 0;
    std::uint64_t voxelsOverOne = 0; ///< voxels whose summed fraction exceeded 1 by more than kOverOneMargin
    double densitySum = 0.0;         ///< output densities
    double rawDensitySum = 0.0;      ///< densities before clamping
    double excessOverOne = 0.0;      ///< sum of (d - 1) over voxels with d > 1, before clamping

    ResolveTally& operator+=(const ResolveTally& o);
    /// Share of the fibre volume that lay above 1 (removed by clamping).
    double excessShare() const { return rawDensitySum > 0.0 ? excessOverOne / rawDensitySum : 0.0; }
};

/// Turns accumulated words into density and orientation. Mean: density is the
/// sum of volume fractions, clamped to 1 with Overlap::Clamp; orientation the
/// principal axis of the structure tensor. Max: the largest sample density and
/// that sample's axis. Voxels with zero density stay inactive. Accumulators
/// with albedo words give VoxelBrick::albedo: the summed weighted colour over
/// the summed volume fraction (before clamping), the density-weighted mean. Adds to `tally`
/// when given. Returns false when no voxel is active.
bool resolveBrick(Reduce reduce, Overlap overlap, const BrickAccumulator& acc, VoxelBrick& out,
                  ResolveTally* tally = nullptr);

/// A sparse result: bricks sorted by key, plus the grid they live in.
struct BrickVolume {
    VoxelGrid grid;
    Reduce reduce = Reduce::Mean;
    std::vector<VoxelBrick> bricks;
    ResolveTally tally; ///< what resolving the bricks found

    std::uint64_t activeVoxelCount() const;
    /// Sum of density times voxel volume (fibre volume, in world units cubed).
    double totalMass() const;
};

/// Resolves accumulators (any order) into a BrickVolume sorted by key, in parallel.
BrickVolume resolveVolume(const VoxelGrid& grid, Reduce reduce, Overlap overlap,
                          std::vector<BrickAccumulator>& accumulators);

/// Principal eigenvector of a symmetric 3x3 matrix (xx yy zz xy xz yz), by
/// cyclic Jacobi rotations: robust when eigenvalues are close.
glm::dvec3 principalAxis(const double tensor[6]);

} // namespace yv

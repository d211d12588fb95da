// Resolved bricks as the GPU resolve reads them back: a header per brick that
// has an active voxel (key, active mask, where its values are, its tally),
// then the values of active voxels only, so the bytes moved from the GPU grow
// with the active voxels rather than with 512 voxels of accumulator words.
// shaders/brick_resolve.comp writes this layout (std430).
#pragma once

#include "core/bricks.h"
#include "core/huge_pages.h"
#include "core/voxel_grid.h"

#include <boost/container/vector.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace yv {

/// One resolved brick (112 bytes, 8-byte aligned for the doubles).
struct PackedBrickHeader {
    std::uint32_t key[2];         ///< brickKey, low word first
    std::uint32_t activeMask[16]; ///< voxel v active: bit v % 32 of word v / 32
    std::uint32_t firstVoxel;     ///< index in PackedBricks::voxels of its first active voxel
    std::uint32_t activeCount;    ///< active voxels (bits set in activeMask), stored in offset order
    std::uint32_t voxelsOverOne;  ///< this brick's ResolveTally, as resolveBrick computes it
    std::uint32_t unused;
    double densitySum, rawDensitySum, excessOverOne;

    std::uint64_t brickKey() const { return std::uint64_t(key[0]) | (std::uint64_t(key[1]) << 32); }
};
static_assert(sizeof(PackedBrickHeader) == 112, "PackedBrickHeader must match shaders/brick_resolve.comp");
static_assert(offsetof(PackedBrickHeader, firstVoxel) == 72 && offsetof(PackedBrickHeader, densitySum) == 88,
              "PackedBrickHeader must match shaders/brick_resolve.comp");

/// One active voxel: density and orientation, as VoxelBrick holds them. Four
/// floats rather than an axis code: the mean axis stays the CPU's to float
/// precision, and a voxel is one aligned 16-byte store on the GPU.
struct PackedVoxel {
    float density;
    float axis[3];
};
static_assert(sizeof(PackedVoxel) == 16, "PackedVoxel must match shaders/brick_resolve.comp");

/// One active voxel's linear colour (--albedo), as VoxelBrick::albedo holds it.
struct PackedAlbedo {
    float rgb[3];
};
static_assert(sizeof(PackedAlbedo) == 12, "PackedAlbedo must match shaders/brick_resolve.comp");

/// A region's resolved bricks, packed. Boost's vector grows without zeroing
/// what append() then overwrites: a region's readback is gigabytes, and
/// zeroing it first on one thread touched every page twice. Its storage is
/// in huge pages where the kernel offers them (core/huge_pages.h).
struct PackedBricks {
    template <typename T>
    using Storage = boost::container::vector<T, HugePageAllocator<T>>;
    Storage<PackedBrickHeader> headers; ///< bricks with an active voxel, in the order they were resolved
    Storage<PackedVoxel> voxels;        ///< each brick's active voxels, bricks one after another
    Storage<PackedAlbedo> albedo;       ///< with --albedo, one per voxel of `voxels`; else empty

    /// Appends bricks whose firstVoxel counts from `voxels` (as one GPU pass
    /// wrote them), shifting them past the voxels already held, and, when
    /// given, the voxels' colours (`a`, voxelCount of them). Large appends are
    /// copied on several threads (the pages they land in too), and so is what
    /// is held when the storage grows.
    void append(const PackedBrickHeader* h, std::size_t brickCount, const PackedVoxel* v, std::size_t voxelCount,
                const PackedAlbedo* a = nullptr);
    std::size_t bytes() const {
        return headers.capacity() * sizeof(PackedBrickHeader) + voxels.capacity() * sizeof(PackedVoxel) +
               albedo.capacity() * sizeof(PackedAlbedo);
    }
    void clear() {
        headers.clear();
        voxels.clear();
        albedo.clear();
    }
};

/// What resolving brick `h` found.
ResolveTally tallyOf(const PackedBrickHeader& h);

/// Unpacks brick `i`: the mask, and density and axis (and colour, where the
/// bricks carry it) of its active voxels (zero elsewhere, as resolveBrick
/// leaves voxels with no density). Throws
/// yv::Error when the header contradicts itself or the voxels.
void unpackBrick(const PackedBricks& packed, std::size_t i, VoxelBrick& out);

/// Brick i's active mask as VoxelBrick::activeMask holds it, checked against
/// its header's count and the voxels held (yv::Error as unpackBrick). Its
/// active voxels are packed.voxels[firstVoxel...] in voxel order.
std::array<std::uint64_t, kBrickVoxels / 64> packedBrickMask(const PackedBricks& packed, std::size_t i);

/// Every brick, unpacked in parallel, in header order; adds their tallies to
/// `tally` in header order (the same bits for the same input).
std::vector<VoxelBrick> unpackBricks(const PackedBricks& packed, ResolveTally* tally = nullptr);

/// All regions' bricks as one volume sorted by key, its tally summed in key
/// order as resolveVolume sums it.
BrickVolume unpackVolume(const VoxelGrid& grid, Reduce reduce, const std::vector<PackedBricks>& regions);

} // namespace yv

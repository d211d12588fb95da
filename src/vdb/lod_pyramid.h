// The level-of-detail pyramid (--lod): level L halves level L-1's
// resolution. A coarse voxel's density is the mean of its 8 children (empty
// children count as 0), so density times voxel volume, the fibre volume, is
// kept level to level; its orientation is the principal axis of the sum of
// its children's structure tensors (density * a a^T at level 0), folded as
// level 0's axes are (canonicalAxis): never an average of vectors, whose
// signs mean nothing.
//
// With albedo, a coarse voxel's colour is its children's colours weighted by
// their densities (the mass-weighted mean): the colour of the fibre it holds.
//
// Each brick gives its parent brick one octant: sums over its blocks of
// voxels. A parent one level up (skip 1, --lod N) takes 4^3 sums over 2^3
// blocks from each of its 8 children; the preview pyramid's first level,
// three levels up (skip 3), takes one sum over the whole brick from each of
// its 512 (lod_request.h). Octants of different children never share a
// voxel, so a parent is built by placing its children's octants, with no sum
// across batches: the result does not depend on how bricks were batched.
#pragma once

#include "core/bricks.h"
#include "core/packed_bricks.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace yv {

/// The most --lod levels a grid allows: the coarsest level keeps at least
/// one brick (8 voxels) on the grid's longest axis.
int maxLodLevels(const VoxelGrid& grid);
/// `levels` when the grid allows it; else throws yv::Error naming the limit.
int checkedLodLevels(int levels, const VoxelGrid& grid);

/// The brick `skip` levels up that `childKey`'s brick falls in.
inline std::uint64_t parentBrickKey(std::uint64_t childKey, int skip = 1) {
    return brickKey(brickCoord(childKey) >> skip);
}

/// The most bytes an octant record takes for `skip` (a mask, then per block
/// a double and 6 floats, and 3 floats with albedo): 2,056 (2,824 with
/// albedo) for skip 1, 40 (52) for skip 3.
std::size_t octantBytesAtMost(int skip, bool albedo);

/// One brick of a coarse level while its children's octants are placed:
/// per voxel the sum of the level-0 descendants' densities and of their
/// structure tensors (xx yy zz xy xz yz), and with albedo of density times
/// colour, over the children `skip` levels below (each voxel covers
/// 2^skip of theirs per axis).
struct CoarseBrick {
    std::uint64_t key = 0;
    bool albedo = false; ///< the octants carry colour sums
    int skip = 1;
    /// Voxels some child reached: only those of the arrays below are
    /// written (placeOctant) and read (resolveCoarseBrick), so clear()
    /// leaves the arrays as they are.
    std::array<std::uint64_t, kBrickVoxels / 64> touched{};
    std::array<double, kBrickVoxels> densitySum{};
    std::array<std::array<double, 6>, kBrickVoxels> tensor{};
    std::array<std::array<double, 3>, kBrickVoxels> albedoSum{};

    void clear(std::uint64_t k, bool withAlbedo = false, int levelsSkipped = 1);
};

/// The octant a level-0 brick gives its parent `skip` levels up (1 to 3),
/// as bytes: a 64-bit mask of the (8 >> skip)^3 blocks of 2^skip voxels a
/// side with an active voxel, then for those blocks the density sums
/// (double), the tensor sums (6 floats) and, when the brick has an albedo,
/// the density-weighted colour sums (3 floats).
void appendOctant(const VoxelBrick& brick, int skip, std::vector<std::uint8_t>& out);
/// The same for brick i of `packed` with active mask `active`
/// (packedBrickMask), read where the GPU's resolve put its voxels.
void appendOctant(const PackedBricks& packed, std::size_t i, const std::array<std::uint64_t, kBrickVoxels / 64>& active,
                  int skip, std::vector<std::uint8_t>& out);
/// The octant a brick of a coarse level gives the level above (skip 1):
/// `resolved` holds its densities as written (so the next level keeps the
/// written mass), `sums` its tensors.
void appendOctant(const CoarseBrick& sums, const VoxelBrick& resolved, std::vector<std::uint8_t>& out);
/// Places the octant bytes of child brick `childKey` into `parent`, the
/// child's skip being parent.skip (with colour sums when parent.albedo).
/// Throws yv::Error when the bytes are not an octant record (a damaged
/// scratch file).
void placeOctant(std::span<const std::uint8_t> bytes, std::uint64_t childKey, CoarseBrick& parent);

/// Densities (the mean over the 8^skip level-below voxels each covers: sum /
/// 8^skip, rounded once to float), orientations and, with albedo, colours
/// (colour sum / density sum) of a coarse brick; a voxel is active where its
/// density is above 0. False when none is.
bool resolveCoarseBrick(const CoarseBrick& sums, VoxelBrick& out);

} // namespace yv

// The streaming writer's leaves (vdb_writer.h): bricks encoded, in
// batches, into OpenVDB leaf records kept in the scratch file, one record per
// grid of a pyramid level, with what the topology and the layout need of
// each leaf.
#pragma once

#include "core/bricks.h"
#include "core/half_floats.h"
#include "core/packed_bricks.h"
#include "core/voxel_statistics.h"
#include "vdb/lod_pyramid.h"
#include "vdb/openvdb_encoding.h"
#include "vdb/spill_file.h"

#include <openvdb/math/Half.h>
#include <openvdb/openvdb.h>

#include <array>
#include <bit>
#include <cstddef>
#include <cstring>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace yv {

/// Grids of one level at most: density, orientation, albedo (GridKind order).
constexpr int kMaxGrids = 3;

/// One leaf in the scratch file: where its records are (one per grid), and
/// its value mask (the topology needs every mask before the first buffer).
struct LeafRecord {
    std::uint64_t order = 0; ///< treeOrderKey
    std::uint64_t at[kMaxGrids] = {};
    std::uint32_t bytes[kMaxGrids] = {};
    std::uint32_t source = 0;
    LeafLoadInfo load[kMaxGrids]; ///< per grid, for the delayed-load metadata
    std::array<std::uint64_t, kBrickVoxels / 64> mask{};
};

/// One level of the pyramid (0: the volume itself): its transform, its
/// grids' encodings (density, orientation, and albedo where the run has it),
/// and its leaves in the scratch file.
struct PyramidLevel {
    int number = 0; ///< L: a voxel covers 2^L level-0 voxels a side
    openvdb::math::Transform::Ptr transform;
    int gridCount = 2;
    openvdb::GridBase::Ptr skeleton[kMaxGrids];
    GridEncoding encoding[kMaxGrids];
    std::unique_ptr<LeafEncoder> encoders[kMaxGrids];
    std::vector<LeafRecord> leaves;
    openvdb::CoordBBox activeBounds;
    std::uint64_t activeVoxels = 0;
    VoxelStatistics statistics; ///< of level 0's values as stored (the file's "yarnvox_statistics")
};

/// Where the octant a brick gives its parent lies, in the scratch file or
/// in memory (OctantOutput): 16 bytes per brick of the level below.
struct OctantRecord {
    std::uint64_t childKey = 0;
    std::uint64_t place = 0; ///< offset << 16 | bytes (an octant is at most 2,824 bytes)
    std::uint64_t at() const { return place >> 16; }
    std::uint32_t bytes() const { return std::uint32_t(place & 0xffff); }
};

/// What encodeBatch makes of each brick for the first coarse level: nothing
/// (skip 0), or its octant for the parent `skip` levels up (lod_pyramid.h),
/// put in the scratch file, or kept in memory (EncodedBatch::octantBytes).
struct OctantOutput {
    int skip = 0;
    bool inMemory = false;
};

/// Leaves encoded from one batch of bricks, in tree order within the batch,
/// and the octants the bricks gave (with an OctantOutput).
struct EncodedBatch {
    std::vector<LeafRecord> records;
    openvdb::CoordBBox bounds;
    std::uint64_t activeVoxels = 0;
    VoxelStatistics statistics; ///< level 0's only
    std::vector<OctantRecord> octants;
    /// The octants' bytes when kept in memory; their places count from its start.
    ByteVector octantBytes;
};

/// The order of a grid's leaves in the file (vdb/tree_order.h), ties by the
/// batch they came in (so a brick given twice sorts next to its twin).
inline bool inTreeOrder(const LeafRecord& a, const LeafRecord& b) {
    return a.order != b.order ? a.order < b.order : a.source < b.source;
}

/// Sorts `leaves` by inTreeOrder (equal ones by their place before). The
/// keys are sorted and the 160-byte records then moved once: sorting the
/// records themselves, moved at every step, took 0.3 to 0.6 s for the last
/// million leaves of the draped garment at 8192 while the disk waited.
void sortInTreeOrder(std::vector<LeafRecord>& leaves);
/// Appends the records of `pieces` to `leaves` in tree order (equal ones in
/// the pieces' order), each moved once: what a stream takes from many
/// regions' batches, sorted without being gathered first.
void appendInTreeOrder(std::span<const std::span<const LeafRecord>> pieces, std::vector<LeafRecord>& leaves);

using BrickMask = std::array<std::uint64_t, kBrickVoxels / 64>;

/// Adds the active voxels' values (density, then the axis: four floats a
/// voxel in `values`, the k-th active one at 4 k) to `s`, as a grid saved
/// with `half` holds them: what a reader gets back. `values` is rounded in place.
inline void countStoredValues(const std::uint64_t* mask, float* values, std::size_t active, bool half,
                              VoxelStatistics& s) {
    if (half) roundThroughHalves(values, values, 4 * active);
    s.addActiveVoxels(mask, true, [&](int, std::size_t k) {
        const float* v = values + 4 * k;
        return VoxelStatistics::ActiveVoxel{v[0], glm::vec3(v[1], v[2], v[3])};
    });
}

/// The bricks encodeBatch takes: voxel bricks...
struct VoxelBrickBatch {
    std::span<const VoxelBrick> bricks;
    std::size_t size() const { return bricks.size(); }
    std::uint64_t key(std::size_t i) const { return bricks[i].key; }
    BrickMask mask(std::size_t i) const { return bricks[i].activeMask; }
    LeafLoadInfo encode(const LeafEncoder& encoder, std::size_t i, const BrickMask&, ByteVector& out) const {
        return encoder.encode(bricks[i], out);
    }
    void octant(std::size_t i, const BrickMask&, int skip, ByteVector& out) const { appendOctant(bricks[i], skip, out); }
    /// Adds brick i's values, as stored, to `s`.
    void count(std::size_t i, const BrickMask& mask, bool half, VoxelStatistics& s) const {
        const VoxelBrick& b = bricks[i];
        float values[4 * kBrickVoxels];
        std::size_t active = 0;
        for (int w = 0; w < kBrickVoxels / 64; ++w)
            for (std::uint64_t bits = mask[w]; bits; bits &= bits - 1, ++active) {
                const int v = w * 64 + std::countr_zero(bits);
                float* to = values + 4 * active;
                to[0] = b.density[v];
                to[1] = b.orientation[v].x;
                to[2] = b.orientation[v].y;
                to[3] = b.orientation[v].z;
            }
        countStoredValues(mask.data(), values, active, half, s);
    }
};

/// ... or the GPU's resolved bricks as they came back, packed: at 8192 filling
/// a VoxelBrick (8 KiB) per brick to encode it was 40 % of the writer
/// threads' time.
struct PackedBrickBatch {
    const PackedBricks& packed;
    std::size_t size() const { return packed.headers.size(); }
    std::uint64_t key(std::size_t i) const { return packed.headers[i].brickKey(); }
    BrickMask mask(std::size_t i) const { return packedBrickMask(packed, i); }
    LeafLoadInfo encode(const LeafEncoder& encoder, std::size_t i, const BrickMask& mask, ByteVector& out) const {
        return encoder.encode(packed, i, mask, out);
    }
    void octant(std::size_t i, const BrickMask& mask, int skip, ByteVector& out) const {
        appendOctant(packed, i, mask, skip, out);
    }
    /// Adds brick i's values, as stored, to `s`.
    void count(std::size_t i, const BrickMask& mask, bool half, VoxelStatistics& s) const {
        // A packed voxel is its density and axis, four floats: the brick's
        // active voxels are the values countStoredValues takes, one after another.
        static_assert(sizeof(PackedVoxel) == 4 * sizeof(float));
        // The mask's count, which packedBrickMask checked against the voxels held.
        const std::size_t active = std::size_t(activeVoxelCount(mask));
        float values[4 * kBrickVoxels];
        std::memcpy(values, packed.voxels.data() + packed.headers[i].firstVoxel, active * sizeof(PackedVoxel));
        countStoredValues(mask.data(), values, active, half, s);
    }
};

/// Encodes `bricks` into leaf records of `level`'s grids in the scratch
/// file, in pieces, and each brick's octant as `octants` says. Defined for
/// VoxelBrickBatch and PackedBrickBatch.
template <typename Batch>
EncodedBatch encodeBatch(const PyramidLevel& level, SpillFile& spill, const Batch& bricks, OctantOutput octants = {});

/// Adds a batch's leaves to `level`, tagged with `source` (for errors).
void addBatch(PyramidLevel& level, EncodedBatch&& batch, std::uint32_t source);

} // namespace yv

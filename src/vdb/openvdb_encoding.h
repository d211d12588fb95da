// The bytes of a .vdb file as OpenVDB 10 writes them, made piece by piece so
// that a writer can produce them without building a tree: the file header,
// each grid's descriptor, metadata and transform (through OpenVDB's own
// classes), internal node records, and leaf buffers (through OpenVDB's own
// value compression, one leaf at a time, on any thread). What the pieces are
// and how they fit together: formats/vdb-subset.md.
#pragma once

#include "core/bricks.h"
#include "core/packed_bricks.h"

#include <openvdb/openvdb.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace yv {

using ByteVector = std::vector<std::uint8_t>;

/// The grids yarnvox writes: density, orientation and, with --albedo, albedo.
enum class GridKind { Density, Orientation, Albedo };

/// How one grid's values are stored: OpenVDB's compression flags for this
/// grid (OpenVDB drops zip for fog volumes, so it can differ per grid) and
/// whether floats are stored as half.
struct GridEncoding {
    GridKind kind = GridKind::Density;
    std::uint32_t compression = 0;
    std::uint32_t archiveCompression = 0; ///< the file's flags, which the delayed-load metadata uses
    bool half = false;
};

/// What OpenVDB's writer records of each leaf in a grid's "file_delayed_load"
/// metadata: the mask compression case, and (with blosc or zip in the file's
/// flags) the bytes of the compressed values plus their 8-byte size.
struct LeafLoadInfo {
    std::int8_t maskMetadata = 0;
    std::int64_t compressedBytes = 0;
};

/// What OpenVDB's writer adds to each grid's metadata (file_bbox_min/max,
/// file_voxel_count, file_mem_bytes), computed from leaves alone.
struct GridStatistics {
    openvdb::CoordBBox activeBounds; ///< default (empty) when no voxel is active
    std::uint64_t activeVoxels = 0;
    std::uint64_t upperNodes = 0, lowerNodes = 0, leaves = 0;
};

/// Encodes leaf buffers exactly as LeafNode::writeBuffers: the value mask,
/// then the values through io::writeCompressedValues. Thread-safe.
class LeafEncoder {
  public:
    explicit LeafEncoder(const GridEncoding& encoding);
    ~LeafEncoder();
    LeafEncoder(const LeafEncoder&) = delete;
    LeafEncoder& operator=(const LeafEncoder&) = delete;
    /// Appends one leaf's buffer record to `out`. Inactive voxels are written as background.
    LeafLoadInfo encode(const VoxelBrick& brick, ByteVector& out) const;
    /// The same record for brick i of `packed` with active mask `mask`
    /// (packedBrickMask), read where the GPU's resolve put its voxels: no
    /// VoxelBrick is filled on the way. Throws yv::Error for an albedo grid
    /// when `packed` has no colours.
    LeafLoadInfo encode(const PackedBricks& packed, std::size_t i, const std::array<std::uint64_t, kBrickVoxels / 64>& mask,
                        ByteVector& out) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// A grid's name: "density", "orientation" or "albedo", with "_lodL" for level L > 0.
std::string gridName(GridKind kind, int lodLevel);

/// A grid with no voxels carrying everything else of the output grid: name,
/// class (density: fog volume), vector type (orientation: invariant, an axis
/// that is not transformed like a position; albedo: invariant, metadata
/// color_space "linear"), transform, half flag, and for
/// level-of-detail grids their level ("lod_level"). Its metadata and
/// transform are what is written.
openvdb::GridBase::Ptr makeSkeletonGrid(GridKind kind, const openvdb::math::Transform::Ptr& transform, bool half,
                                        int lodLevel = 0);

/// The compression OpenVDB's archive with `archiveFlags` uses for `skeleton`.
std::uint32_t gridCompression(std::uint32_t archiveFlags, const openvdb::GridBase& skeleton);

/// File header (magic, versions, a new UUID), file metadata and grid count.
ByteVector fileHeaderBytes(const openvdb::MetaMap& fileMetadata, std::int32_t gridCount);

/// One grid's bytes before its topology: descriptor, stream positions,
/// compression, metadata (with `stats` and the leaves' delayed-load records,
/// in tree order, added as OpenVDB adds them) and transform. `positionsAt`
/// receives where the 24 bytes of stream positions lie in the result, to be
/// patched by patchStreamPositions once known.
ByteVector gridPrefixBytes(const openvdb::GridBase& skeleton, const GridEncoding& encoding,
                           const GridStatistics& stats, std::span<const LeafLoadInfo> leaves,
                           std::size_t& positionsAt);
/// Writes the descriptor's grid, block and end positions (absolute file offsets) at `positionsAt`.
void patchStreamPositions(ByteVector& prefix, std::size_t positionsAt, const openvdb::GridBase& skeleton,
                          bool half, std::int64_t gridPos, std::int64_t blockPos, std::int64_t endPos);

/// The tree's first topology bytes (buffer count, root background, tile and child counts).
ByteVector treeTopologyHeader(const GridEncoding& encoding, std::uint32_t rootChildren);
/// An internal node's value record (all tiles inactive background): it does
/// not depend on which children the node has. log2Dim 5 (upper) or 4 (lower).
ByteVector internalNodeValues(const GridEncoding& encoding, int log2Dim);

} // namespace yv

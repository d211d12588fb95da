// Where a grid's bytes come from when the .vdb is written: its topology,
// made from the leaf records in tree order, and its leaf records, read from
// the scratch file chunk by chunk of the output (formats/vdb-subset.md).
#pragma once

#include "core/default_init_allocator.h"
#include "vdb/leaf_batches.h"
#include "vdb/openvdb_encoding.h"
#include "vdb/spill_file.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace yv {

/// Bytes left uninitialized when sized: the topology is written whole, side by side.
using TopologyBytes = std::vector<std::uint8_t, DefaultInitAllocator<std::uint8_t>>;

/// One grid's topology (formats/vdb-subset.md) from records in tree order:
/// root children, their 32^3 and 16^3 internal nodes (child mask, an empty
/// value mask, the tile values), and each leaf's value mask. Where each node
/// goes is found in one pass over the leaves; the nodes are then written side
/// by side (at 8192 a grid's topology is about 1 GB).
TopologyBytes topologyBytes(const std::vector<LeafRecord>& leaves, const GridEncoding& encoding);

/// Consecutive leaf records of one grid, [begin, end) of its level's leaves
/// in tree order, at `at` in the output: the index that finds which records
/// a chunk of the output holds.
struct RecordPiece {
    const std::vector<LeafRecord>* leaves;
    int grid;
    std::size_t begin, end;
    std::uint64_t at, bytes;
};

/// Cuts one grid's records of leaves [begin, end of `leaves`), laid out from
/// `at`, into pieces of about kRecordPieceBytes.
void addRecordPieces(const std::vector<LeafRecord>& leaves, int grid, std::uint64_t at, std::vector<RecordPiece>& out,
                     std::size_t begin = 0);

/// Fills out[0, n) with output bytes [at, at + n) from the records of
/// `pieces` (in file order) that overlap it: runs of records that follow
/// each other in the scratch file are read with one call.
void fillFromRecords(const std::vector<RecordPiece>& pieces, const SpillFile& spill, std::uint64_t at,
                     std::span<std::uint8_t> out);

} // namespace yv

// The values of a yarnvox .vdb's leaves (vdb/vdb_index.h), read a range of
// leaves at a time: a grid's records for consecutive leaves are one run of
// bytes, so a range is one read, decoded on any thread.
#pragma once

#include "vdb/vdb_index.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace yv {

/// Reads the records of leaves [first, last) of `table` into `bytes`.
void readLeafRecords(const VdbIndex& index, const VdbGridInfo& grid, const VdbLeafTable& table, std::size_t first,
                     std::size_t last, std::vector<std::uint8_t>& bytes);

/// Decodes the record of leaf number `leaf` (brick `brick`, its bytes in
/// `record`, read from byte `recordAt`) into `out`: 512 floats for a float
/// grid, 512 x 3 for a vector grid, in OpenVDB's voxel order, inactive
/// voxels 0. Throws yv::Error naming the file, the grid, the leaf, its voxel
/// and byte when the record is not what the topology declared or a value is
/// not finite. With `activeOut`, puts the leaf's 8 words of active voxels there.
void decodeLeafRecord(std::span<const std::uint8_t> record, const VdbIndex& index, const VdbGridInfo& grid,
                      std::size_t leaf, glm::ivec3 brick, std::uint64_t recordAt, float* out,
                      std::uint64_t* activeOut = nullptr);

} // namespace yv

// The octants of the preview pyramid's first level (lod_request.h) kept in
// memory instead of the scratch file: one record of sums per level-0 brick,
// 40 bytes (52 with albedo). Read back from the scratch file, each would be a
// system call for 40 bytes; in memory, with its 16-byte place, it is about a
// quarter of what level 0's index holds per leaf. The full pyramid's octants
// (up to 2 KB a brick) stay in the scratch file.
#pragma once

#include "vdb/leaf_batches.h"

#include <cstdint>
#include <span>
#include <vector>

namespace yv {

class OctantMemory {
  public:
    /// Keeps `bytes`, the octants of `records` (their places counting from
    /// the start of `bytes`), and moves their places to where they now lie.
    /// Not thread-safe: the writer calls it under its lock.
    void keep(std::span<OctantRecord> records, std::span<const std::uint8_t> bytes);
    /// Record r's bytes; throws yv::Error when it lies beyond what was kept.
    std::span<const std::uint8_t> bytes(const OctantRecord& r) const;
    /// Bytes held, chunks' unused ends included.
    std::uint64_t heldBytes() const { return std::uint64_t(chunks_.size()) * kChunkBytes; }

  private:
    /// Chunks of fixed capacity, a record never across two: growing one
    /// vector copied it whole each time (transiently three times its size).
    static constexpr std::uint64_t kChunkBytes = 16u << 20;
    std::vector<ByteVector> chunks_;
};

} // namespace yv

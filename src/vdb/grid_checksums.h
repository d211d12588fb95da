// A checksum of each grid's bytes in a yarnvox .vdb (formats/vdb-subset.md,
// "Checksums"): the file metadata item yarnvox_grid_xxh64 lists, grid by grid
// in file order, an XXH64 of the grid's bytes, so a flipped byte anywhere in
// a grid is found (inspect --verify, export) where the structure still reads.
//
// A grid's bytes run from its descriptor (its name) to its end position. They
// are cut at every multiple of 4096 of the file offset: each piece's XXH64
// (seed 0), little-endian, back to back, is hashed again (XXH64, seed 0).
// The pieces let the writer hash the chunks it fills in parallel (vdb/
// chunked_output.h: chunks start at multiples of 4096), with no second pass.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace yv {

class VdbIndex;

/// The file metadata item's name.
inline constexpr const char* kGridChecksumsName = "yarnvox_grid_xxh64";
/// Where a grid's bytes are cut.
inline constexpr std::uint64_t kChecksumBlockBytes = 4096;

/// The checksum of bytes [begin, end) of a file, from pieces added in any order.
class RangeChecksum {
  public:
    RangeChecksum(std::uint64_t begin, std::uint64_t end);
    /// Hashes the part of the range within `bytes`, which lie at file offset
    /// `at`: a multiple of kChecksumBlockBytes, and `bytes` reach the range's
    /// end or a multiple of it. Thread-safe for disjoint `bytes`.
    void add(std::uint64_t at, std::span<const std::uint8_t> bytes);
    /// The piece of the whole block at `at` (a multiple of
    /// kChecksumBlockBytes, inside the range), hashed where it was written:
    /// XXH64 of its kChecksumBlockBytes bytes, seed 0 (blockChecksum).
    void setBlock(std::uint64_t at, std::uint64_t hash);
    /// The range's checksum (every piece added).
    std::uint64_t value() const;
    std::uint64_t begin() const { return begin_; }
    std::uint64_t end() const { return end_; }

  private:
    std::uint64_t begin_, end_;
    std::vector<std::uint64_t> pieces_; ///< one per 4096-byte block the range meets
};

/// A whole block's piece, for RangeChecksum::setBlock.
std::uint64_t blockChecksum(std::span<const std::uint8_t> block);

/// The item's text: "NAME=HEX" for each grid, 16 hex digits each, separated
/// by spaces (the same length whatever the sums: the writer puts zeros in
/// first, and the real sums once the grids are written).
std::string checksumText(const std::vector<std::string>& gridNames, const std::vector<std::uint64_t>& sums);

/// Checks every grid of `index` against the checksums its file records.
/// Returns the number of grids checked, 0 when the file records none (older
/// yarnvox files, other writers). Throws yv::Error, one line naming the file
/// and the grid whose bytes changed (or the malformed item).
std::size_t verifyGridChecksums(const VdbIndex& index);

} // namespace yv

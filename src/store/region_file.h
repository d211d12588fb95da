// Region files of the brick store: layout, encoding, and every check a
// reader makes (formats/brick-store.md, "Region file"). Bytes in memory only;
// brick_store.cpp reads and writes the files.
#pragma once

#include "core/bricks.h"
#include "store/manifest.h"

#include <glm/vec3.hpp>
#include <xxhash.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace yv {

/// XXH64 with seed 0 (libxxhash): the checksum of region files.
inline std::uint64_t xxh64(const void* data, std::size_t size) { return XXH64(data, size, 0); }

constexpr std::size_t kRegionHeaderSize = 160;

/// A region file's header, decoded.
struct RegionHeader {
    std::uint64_t fingerprint = 0, id = 0;
    glm::ivec3 min{0}, max{0};
    VoxelGrid grid;
    Reduce reduce = Reduce::Mean;
    std::uint64_t brickCount = 0, activeVoxels = 0, payloadSize = 0, storedSize = 0;
    std::uint32_t chunkCount = 0;
    bool albedo = false; ///< every brick carries VoxelBrick::albedo (flag bit 0)
    std::uint64_t tableChecksum = 0;

    std::uint64_t indexOffset() const { return kRegionHeaderSize; }
    std::uint64_t tableOffset() const { return kRegionHeaderSize + 8 * brickCount; }
    std::uint64_t dataOffset() const { return tableOffset() + 24 * std::uint64_t(chunkCount); }
    std::uint64_t fileSize() const { return dataOffset() + storedSize; }
};

/// A region file ready to write, in three parts written back to back.
struct EncodedRegion {
    std::array<std::uint8_t, kRegionHeaderSize> header;
    std::vector<std::uint8_t> table; ///< key index, then the chunk table
    std::vector<std::vector<std::uint8_t>> chunks;
    RegionHeader info;
};

/// Encodes the bricks of region `id` of run `run` (any order; stored sorted by
/// key), compressing chunks in parallel. Throws yv::Error, naming `name`, on a
/// brick given twice or one that does not overlap [min, max).
EncodedRegion encodeRegion(const StoreManifest& run, std::uint64_t id, glm::ivec3 min, glm::ivec3 max,
                           const std::vector<VoxelBrick>& bricks, const std::string& name);

/// Checks and decodes a header, and that `fileSize` is the size it describes.
/// `p` holds min(fileSize, kRegionHeaderSize) bytes; `name` is used in errors.
RegionHeader parseRegionHeader(const std::uint8_t* p, std::uint64_t fileSize, const std::string& name);

/// Throws yv::Error unless the header belongs to `run` and region `id` (and
/// has bounds [*min, *max) when those are given).
void checkRegionIdentity(const RegionHeader& h, const StoreManifest& run, std::uint64_t id, const glm::ivec3* min,
                         const glm::ivec3* max, const std::string& name);

/// Verifies everything after the header of the whole file `p` (whose header is
/// `h`) and, when `out` is given, decodes the bricks into it, sorted by key.
void decodeRegionBody(const std::uint8_t* p, const RegionHeader& h, const std::string& name,
                      std::vector<VoxelBrick>* out);

/// One lz4 chunk of a region file, as its table entry describes it.
struct RegionChunk {
    std::uint64_t offset = 0, stored = 0, raw = 0; ///< file offset and sizes in bytes
    std::uint64_t firstBrick = 0;                   ///< index of its first brick in the key index
    std::uint64_t storedSum = 0, rawSum = 0;        ///< XXH64 before and after decompression
};

/// A region file's key index and chunk table, checked.
struct RegionTable {
    std::vector<std::uint64_t> keys; ///< ascending
    std::vector<RegionChunk> chunks;
};

/// Checks and decodes the bytes between the header and the data (the key
/// index and chunk table: h.dataOffset() - h.indexOffset() of them at `table`):
/// their checksum, the keys' order and bounds, and that the chunks cover
/// every brick and the file's data exactly.
RegionTable parseRegionTable(const std::uint8_t* table, const RegionHeader& h, const std::string& name);

/// The bricks of one decoded chunk, in the file's own layout (mask words,
/// densities, axes, then albedo where the run has it), read in place.
struct RawBricks {
    const std::uint64_t* keys = nullptr; ///< `count` keys, ascending
    const std::uint8_t* raw = nullptr;
    std::size_t count = 0;
    std::size_t stride = 0; ///< bytes per brick

    const std::uint64_t* activeMask(std::size_t i) const {
        return reinterpret_cast<const std::uint64_t*>(raw + i * stride);
    }
    const float* density(std::size_t i) const { return reinterpret_cast<const float*>(raw + i * stride + 64); }
    const glm::vec3* orientation(std::size_t i) const {
        return reinterpret_cast<const glm::vec3*>(raw + i * stride + 64 + 4 * kBrickVoxels);
    }
};

/// Decompresses chunk `c` of `table` from its stored bytes `stored` into
/// `raw` (resized; reused across calls) after checking both checksums, and
/// returns its bricks. Throws yv::Error naming `name`, the chunk and its bytes.
RawBricks decodeRegionChunk(const std::uint8_t* stored, const RegionTable& table, std::uint32_t c,
                            const RegionHeader& h, const std::string& name, std::vector<std::uint8_t>& raw);

/// Active voxels of the bricks (popcount of their masks).
std::uint64_t countActive(const RawBricks& bricks);

/// Throws yv::Error unless `counted`, the active voxels of every chunk, is
/// what the header says.
void checkActiveCount(const RegionHeader& h, std::uint64_t counted, const std::string& name);

} // namespace yv

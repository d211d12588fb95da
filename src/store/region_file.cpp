// Region files: layout, encoding, verification (formats/brick-store.md, "Region file").
#include "store/region_file.h"

#include "core/error.h"
#include "core/text.h"

#include <lz4.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cinttypes>
#include <climits>
#include <cstdio>
#include <cstring>
#include <numeric>

namespace yv {
namespace {

// Bytes are assembled by hand so the format stays little-endian on any host.
void put(std::uint8_t* p, std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}
std::uint64_t get(const std::uint8_t* p, int n) {
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i) v |= std::uint64_t{p[i]} << (8 * i);
    return v;
}

// Layout constants (formats/brick-store.md).
constexpr char kMagic[8] = {'Y', 'V', 'B', 'R', 'I', 'C', 'K', 'S'};
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kHeaderSize = kRegionHeaderSize;
constexpr std::size_t kChunkEntrySize = 24; // RegionHeader::dataOffset() spells it out too
constexpr std::size_t kMaskBytes = 8 * 8, kDensityBytes = 4 * kBrickVoxels, kOrientationBytes = 12 * kBrickVoxels;
constexpr std::size_t kBrickBytes = kMaskBytes + kDensityBytes + kOrientationBytes; // 8256
constexpr std::size_t kAlbedoBytes = 12 * kBrickVoxels; // after the orientation, in runs with --albedo
constexpr std::uint32_t kFlagAlbedo = 1;                 // header flags (bytes 140..143)
std::size_t brickBytes(bool albedo) { return kBrickBytes + (albedo ? kAlbedoBytes : 0); }
// Chunks keep every lz4 call far below its 2 GB limit, bound the scratch
// memory per thread, and let one region compress on several cores.
constexpr std::size_t kBricksPerChunk = 2048;              // what we write: 16.1 MiB raw
constexpr std::size_t kMaxChunkRawBytes = 64u << 20;        // what we accept

// Payload bytes are copied straight from memory (fast for hundreds of MB),
// which matches the little-endian format only on a little-endian host.
static_assert(std::endian::native == std::endian::little, "the brick store format assumes a little-endian host");
static_assert(sizeof(glm::vec3) == 12);

[[noreturn]] void fail(const std::string& name, std::uint64_t offset, const std::string& what) {
    throw Error(name + ": byte " + std::to_string(offset) + ": " + what);
}

void putVec(std::uint8_t* p, glm::ivec3 v) {
    for (int i = 0; i < 3; ++i) put(p + 4 * i, static_cast<std::uint32_t>(v[i]), 4);
}
glm::ivec3 getVec(const std::uint8_t* p) {
    glm::ivec3 v;
    for (int i = 0; i < 3; ++i) v[i] = static_cast<std::int32_t>(get(p + 4 * i, 4));
    return v;
}

std::array<std::uint8_t, kHeaderSize> encodeHeader(const RegionHeader& h) {
    std::array<std::uint8_t, kHeaderSize> b{};
    std::memcpy(b.data(), kMagic, 8);
    put(&b[8], kVersion, 4);
    put(&b[12], kHeaderSize, 4);
    put(&b[16], h.fingerprint, 8);
    put(&b[24], h.id, 8);
    putVec(&b[32], h.min);
    putVec(&b[44], h.max);
    put(&b[56], std::bit_cast<std::uint64_t>(h.grid.voxelSize), 8);
    for (int i = 0; i < 3; ++i) put(&b[64 + 8 * i], std::bit_cast<std::uint64_t>(h.grid.origin[i]), 8);
    putVec(&b[88], h.grid.dims);
    put(&b[100], h.reduce == Reduce::Max ? 1 : 0, 4);
    put(&b[104], h.brickCount, 8);
    put(&b[112], h.activeVoxels, 8);
    put(&b[120], h.payloadSize, 8);
    put(&b[128], h.storedSize, 8);
    put(&b[136], h.chunkCount, 4);
    put(&b[140], h.albedo ? kFlagAlbedo : 0, 4);
    put(&b[144], h.tableChecksum, 8);
    put(&b[152], xxh64(b.data(), 152), 8);
    return b;
}

bool overlaps(std::uint64_t key, glm::ivec3 min, glm::ivec3 max) {
    const glm::ivec3 lo = brickCoord(key) * kBrickSize;
    for (int i = 0; i < 3; ++i)
        if (lo[i] >= max[i] || lo[i] + kBrickSize <= min[i]) return false;
    return true;
}

void serializeBrick(const VoxelBrick& b, std::uint8_t* dst) {
    std::memcpy(dst, b.activeMask.data(), kMaskBytes);
    std::memcpy(dst + kMaskBytes, b.density.data(), kDensityBytes);
    std::memcpy(dst + kMaskBytes + kDensityBytes, b.orientation.data(), kOrientationBytes);
    if (!b.albedo.empty()) std::memcpy(dst + kBrickBytes, b.albedo.data(), kAlbedoBytes);
}

void deserializeBrick(const std::uint8_t* src, std::uint64_t key, bool albedo, VoxelBrick& b) {
    b.key = key;
    std::memcpy(b.activeMask.data(), src, kMaskBytes);
    std::memcpy(b.density.data(), src + kMaskBytes, kDensityBytes);
    std::memcpy(b.orientation.data(), src + kMaskBytes + kDensityBytes, kOrientationBytes);
    b.albedo.clear();
    if (albedo) {
        b.albedo.resize(kBrickVoxels);
        std::memcpy(b.albedo.data(), src + kBrickBytes, kAlbedoBytes);
    }
}

std::uint64_t countActive(const std::uint8_t* raw, std::size_t bricks, std::size_t bytesPerBrick) {
    std::uint64_t n = 0;
    for (std::size_t i = 0; i < bricks; ++i)
        for (int w = 0; w < 8; ++w) n += std::popcount(get(raw + i * bytesPerBrick + 8 * w, 8));
    return n;
}

} // namespace

RegionHeader parseRegionHeader(const std::uint8_t* p, std::uint64_t fileSize, const std::string& name) {
    // The magic goes first so a foreign or short file is called that, not "truncated".
    const std::size_t magicLen = std::min<std::uint64_t>(fileSize, 8);
    if (std::memcmp(p, kMagic, magicLen) != 0) {
        std::string found;
        for (std::size_t i = 0; i < magicLen; ++i) {
            char c[8];
            std::snprintf(c, sizeof c, p[i] >= 0x20 && p[i] < 0x7f ? "%c" : "\\x%02x", p[i]);
            found += c;
        }
        fail(name, 0, "expected magic \"YVBRICKS\" (a yarnvox region file), found \"" + found + "\"");
    }
    if (fileSize < kHeaderSize)
        fail(name, fileSize, "truncated header: expected " + std::to_string(kHeaderSize) + " bytes, file ends");
    if (const std::uint64_t v = get(p + 8, 4); v != kVersion)
        fail(name, 8, "unsupported region file version " + std::to_string(v) + ": expected " +
                          std::to_string(kVersion) + " (written by another yarnvox version?)");
    if (const std::uint64_t hs = get(p + 12, 4); hs != kHeaderSize)
        fail(name, 12, "header size " + std::to_string(hs) + ": expected " + std::to_string(kHeaderSize));
    if (const std::uint64_t stored = get(p + 152, 8), computed = xxh64(p, 152); stored != computed)
        fail(name, 152, "header checksum mismatch (stored " + hex64(stored) + ", computed " + hex64(computed) +
                            "): the header is damaged");

    // The checksum matched: what follows can only fail for a file we did not write.
    RegionHeader h;
    h.fingerprint = get(p + 16, 8);
    h.id = get(p + 24, 8);
    h.min = getVec(p + 32);
    h.max = getVec(p + 44);
    h.grid.voxelSize = std::bit_cast<double>(get(p + 56, 8));
    for (int i = 0; i < 3; ++i) h.grid.origin[i] = std::bit_cast<double>(get(p + 64 + 8 * i, 8));
    h.grid.dims = getVec(p + 88);
    const std::uint64_t reduce = get(p + 100, 4);
    if (reduce > 1) fail(name, 100, "reduce mode " + std::to_string(reduce) + ": expected 0 (mean) or 1 (max)");
    h.reduce = reduce == 1 ? Reduce::Max : Reduce::Mean;
    h.brickCount = get(p + 104, 8);
    h.activeVoxels = get(p + 112, 8);
    h.payloadSize = get(p + 120, 8);
    h.storedSize = get(p + 128, 8);
    h.chunkCount = static_cast<std::uint32_t>(get(p + 136, 4));
    h.tableChecksum = get(p + 144, 8);
    const std::uint64_t flags = get(p + 140, 4);
    if (flags & ~std::uint64_t(kFlagAlbedo)) fail(name, 140, "unknown flags " + std::to_string(flags) + ": expected 0 or 1 (albedo)");
    h.albedo = flags & kFlagAlbedo;
    const std::size_t bytesPerBrick = brickBytes(h.albedo);
    // Each count is bounded by the file size before it is multiplied, so no product can overflow.
    if (h.brickCount > fileSize / 8 || h.chunkCount > fileSize / kChunkEntrySize || h.storedSize > fileSize)
        fail(name, 104, "brick count " + std::to_string(h.brickCount) + ", chunk count " +
                            std::to_string(h.chunkCount) + " and stored size " + std::to_string(h.storedSize) +
                            " cannot fit in a file of " + std::to_string(fileSize) + " bytes (truncated?)");
    if (h.payloadSize != h.brickCount * bytesPerBrick)
        fail(name, 120, "payload size " + std::to_string(h.payloadSize) + ": expected " +
                            std::to_string(bytesPerBrick) + " bytes per brick for " + std::to_string(h.brickCount) +
                            " bricks");
    if ((h.brickCount == 0) != (h.chunkCount == 0) || h.chunkCount > h.brickCount)
        fail(name, 136, "chunk count " + std::to_string(h.chunkCount) + " does not fit " +
                            std::to_string(h.brickCount) + " bricks");
    if (h.activeVoxels > h.brickCount * kBrickVoxels)
        fail(name, 112, "active voxel count " + std::to_string(h.activeVoxels) + " exceeds 512 per brick");
    if (fileSize < h.fileSize())
        fail(name, fileSize, "truncated: the header describes " + std::to_string(h.fileSize()) +
                                 " bytes, the file has " + std::to_string(fileSize));
    if (fileSize > h.fileSize())
        fail(name, h.fileSize(), std::to_string(fileSize - h.fileSize()) +
                                     " trailing bytes after the last chunk: expected end of file");
    return h;
}

void checkRegionIdentity(const RegionHeader& h, const StoreManifest& m, std::uint64_t id, const glm::ivec3* min,
                         const glm::ivec3* max, const std::string& name) {
    if (h.fingerprint != m.fingerprint)
        fail(name, 16, "region belongs to another run (fingerprint " + hex64(h.fingerprint) + ", the work dir's " +
                           hex64(m.fingerprint) + ")");
    if (h.id != id) fail(name, 24, "holds region " + std::to_string(h.id) + ", expected " + std::to_string(id));
    if (!sameGrid(h.grid, m.grid)) fail(name, 56, "grid differs from the work dir's manifest");
    if (h.reduce != m.reduce)
        fail(name, 100, std::string("reduce mode ") + toString(h.reduce) + ", the work dir's is " + toString(m.reduce));
    if (min && max && (h.min != *min || h.max != *max))
        fail(name, 32, "bounds " + coordText(h.min) + "-" + coordText(h.max) + " differ from the plan's " + coordText(*min) + "-" +
                           coordText(*max));
}

EncodedRegion encodeRegion(const StoreManifest& m, std::uint64_t id, glm::ivec3 min, glm::ivec3 max,
                           const std::vector<VoxelBrick>& bricks, const std::string& name) {
    // Sorting indices moves 8 bytes per brick instead of 8 KB.
    if (bricks.size() > UINT32_MAX) throw Error("cannot write " + name + ": too many bricks for one region");
    std::vector<std::uint32_t> order(bricks.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](auto a, auto b) { return bricks[a].key < bricks[b].key; });
    for (std::size_t i = 0; i < order.size(); ++i) {
        const std::uint64_t key = bricks[order[i]].key;
        if (i > 0 && key == bricks[order[i - 1]].key)
            throw Error("cannot write " + name + ": brick " + coordText(brickCoord(key)) + " given twice");
        if (key >> 63 || !overlaps(key, min, max))
            throw Error("cannot write " + name + ": brick " + coordText(brickCoord(key)) + " lies outside the region " +
                        coordText(min) + "-" + coordText(max));
    }

    EncodedRegion e;
    RegionHeader& h = e.info;
    h.fingerprint = m.fingerprint;
    h.id = id;
    h.min = min;
    h.max = max;
    h.grid = m.grid;
    h.reduce = m.reduce;
    h.brickCount = bricks.size();
    h.albedo = !bricks.empty() && !bricks.front().albedo.empty();
    for (const VoxelBrick& b : bricks)
        if (b.albedo.size() != (h.albedo ? std::size_t(kBrickVoxels) : 0))
            throw Error("cannot write " + name + ": brick " + coordText(brickCoord(b.key)) +
                        (h.albedo ? " has no albedo, others have" : " has albedo, others have none"));
    const std::size_t bytesPerBrick = brickBytes(h.albedo);
    h.payloadSize = h.brickCount * bytesPerBrick;
    h.chunkCount = static_cast<std::uint32_t>((bricks.size() + kBricksPerChunk - 1) / kBricksPerChunk);

    e.chunks.resize(h.chunkCount);
    e.table.resize(8 * h.brickCount + kChunkEntrySize * h.chunkCount);
    for (std::size_t i = 0; i < order.size(); ++i) put(&e.table[8 * i], bricks[order[i]].key, 8);
    std::vector<std::uint64_t> active(h.chunkCount);
    tbb::parallel_for(std::uint32_t(0), h.chunkCount, [&](std::uint32_t c) {
        const std::size_t first = std::size_t(c) * kBricksPerChunk;
        const std::size_t n = std::min(kBricksPerChunk, bricks.size() - first);
        std::vector<std::uint8_t> raw(n * bytesPerBrick);
        for (std::size_t i = 0; i < n; ++i) serializeBrick(bricks[order[first + i]], &raw[i * bytesPerBrick]);
        std::vector<std::uint8_t>& out = e.chunks[c];
        out.resize(static_cast<std::size_t>(LZ4_compressBound(static_cast<int>(raw.size()))));
        const int stored = LZ4_compress_default(reinterpret_cast<const char*>(raw.data()),
                                                reinterpret_cast<char*>(out.data()), static_cast<int>(raw.size()),
                                                static_cast<int>(out.size()));
        YV_CHECK(stored > 0);
        out.resize(static_cast<std::size_t>(stored));
        std::uint8_t* entry = &e.table[8 * h.brickCount + kChunkEntrySize * c];
        put(entry, out.size(), 4);
        put(entry + 4, raw.size(), 4);
        put(entry + 8, xxh64(out.data(), out.size()), 8);
        put(entry + 16, xxh64(raw.data(), raw.size()), 8);
        active[c] = countActive(raw.data(), n, bytesPerBrick);
    });
    for (std::uint32_t c = 0; c < h.chunkCount; ++c) {
        h.storedSize += e.chunks[c].size();
        h.activeVoxels += active[c];
    }
    h.tableChecksum = xxh64(e.table.data(), e.table.size());
    e.header = encodeHeader(h);
    return e;
}

RegionTable parseRegionTable(const std::uint8_t* table, const RegionHeader& h, const std::string& name) {
    const std::size_t bytesPerBrick = brickBytes(h.albedo);
    const std::uint64_t tableEnd = h.dataOffset();
    if (const std::uint64_t computed = xxh64(table, tableEnd - h.indexOffset()); computed != h.tableChecksum)
        fail(name, h.indexOffset(), "checksum mismatch over the brick index and chunk table (bytes " +
                                        std::to_string(h.indexOffset()) + ".." + std::to_string(tableEnd) +
                                        "): the file is damaged");

    RegionTable t;
    t.keys.resize(h.brickCount);
    for (std::uint64_t i = 0; i < h.brickCount; ++i) {
        const std::uint64_t key = t.keys[i] = get(table + 8 * i, 8);
        if (key >> 63 || (i > 0 && key <= t.keys[i - 1]))
            fail(name, h.indexOffset() + 8 * i, "brick key " + hex64(key) + ": expected keys in ascending order");
        if (!overlaps(key, h.min, h.max))
            fail(name, h.indexOffset() + 8 * i, "brick " + coordText(brickCoord(key)) + " lies outside the region " +
                                                    coordText(h.min) + "-" + coordText(h.max));
    }

    t.chunks.resize(h.chunkCount);
    std::uint64_t offset = tableEnd, brick = 0;
    for (std::uint32_t c = 0; c < h.chunkCount; ++c) {
        const std::uint64_t at = h.tableOffset() + kChunkEntrySize * c;
        const std::uint8_t* entry = table + (at - h.indexOffset());
        RegionChunk& k = t.chunks[c];
        k = {offset, get(entry, 4), get(entry + 4, 4), brick, get(entry + 8, 8), get(entry + 16, 8)};
        if (k.raw == 0 || k.raw % bytesPerBrick != 0 || k.raw > kMaxChunkRawBytes)
            fail(name, at + 4, "chunk " + std::to_string(c) + " raw size " + std::to_string(k.raw) +
                                   ": expected a positive multiple of " + std::to_string(bytesPerBrick) +
                                   " bytes, at most " + std::to_string(kMaxChunkRawBytes));
        if (k.stored > static_cast<std::uint64_t>(LZ4_compressBound(static_cast<int>(k.raw))) ||
            k.stored > h.fileSize() - offset)
            fail(name, at, "chunk " + std::to_string(c) + " stored size " + std::to_string(k.stored) +
                               " is impossible for " + std::to_string(k.raw) + " raw bytes here");
        offset += k.stored;
        brick += k.raw / bytesPerBrick;
    }
    if (brick != h.brickCount || offset != h.fileSize())
        fail(name, h.tableOffset(), "chunk table covers " + std::to_string(brick) + " bricks in " +
                                        std::to_string(offset - tableEnd) + " bytes, the header says " +
                                        std::to_string(h.brickCount) + " bricks in " + std::to_string(h.storedSize));
    return t;
}

RawBricks decodeRegionChunk(const std::uint8_t* stored, const RegionTable& t, std::uint32_t c, const RegionHeader& h,
                            const std::string& name, std::vector<std::uint8_t>& raw) {
    const RegionChunk& k = t.chunks[c];
    const auto where = [&] {
        return name + ": byte " + std::to_string(k.offset) + ": chunk " + std::to_string(c) + " of " +
               std::to_string(t.chunks.size()) + " (bytes " + std::to_string(k.offset) + ".." +
               std::to_string(k.offset + k.stored) + ")";
    };
    if (xxh64(stored, k.stored) != k.storedSum) throw Error(where() + ": checksum mismatch: the compressed data is damaged");
    raw.resize(k.raw);
    const int got = LZ4_decompress_safe(reinterpret_cast<const char*>(stored), reinterpret_cast<char*>(raw.data()),
                                        static_cast<int>(k.stored), static_cast<int>(k.raw));
    if (got != static_cast<int>(k.raw))
        throw Error(where() + ": lz4 data does not decompress to " + std::to_string(k.raw) + " bytes");
    if (xxh64(raw.data(), raw.size()) != k.rawSum) throw Error(where() + ": checksum mismatch after decompression");
    const std::size_t stride = brickBytes(h.albedo);
    return RawBricks{t.keys.data() + k.firstBrick, raw.data(), k.raw / stride, stride};
}

std::uint64_t countActive(const RawBricks& b) { return countActive(b.raw, b.count, b.stride); }

void decodeRegionBody(const std::uint8_t* p, const RegionHeader& h, const std::string& name,
                      std::vector<VoxelBrick>* out) {
    const RegionTable t = parseRegionTable(p + h.indexOffset(), h, name);
    if (out) out->resize(h.brickCount);
    // Errors are kept per chunk and the first reported, so the message does
    // not depend on which thread got there first.
    std::vector<std::string> errors(h.chunkCount);
    std::vector<std::uint64_t> active(h.chunkCount);
    tbb::parallel_for(std::uint32_t(0), h.chunkCount, [&](std::uint32_t c) {
        std::vector<std::uint8_t> raw;
        try {
            const RawBricks b = decodeRegionChunk(p + t.chunks[c].offset, t, c, h, name, raw);
            active[c] = countActive(b);
            if (out)
                for (std::size_t i = 0; i < b.count; ++i)
                    deserializeBrick(b.raw + i * b.stride, b.keys[i], h.albedo, (*out)[t.chunks[c].firstBrick + i]);
        } catch (const Error& e) {
            errors[c] = e.what();
        }
    });
    for (const std::string& e : errors)
        if (!e.empty()) throw Error(e);
    checkActiveCount(h, std::accumulate(active.begin(), active.end(), std::uint64_t(0)), name);
}

void checkActiveCount(const RegionHeader& h, std::uint64_t counted, const std::string& name) {
    if (counted != h.activeVoxels)
        fail(name, 112, "the header counts " + std::to_string(h.activeVoxels) + " active voxels, the bricks hold " +
                            std::to_string(counted));
}

} // namespace yv

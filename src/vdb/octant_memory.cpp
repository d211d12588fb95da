#include "vdb/octant_memory.h"

#include "core/error.h"

namespace yv {

void OctantMemory::keep(std::span<OctantRecord> records, std::span<const std::uint8_t> bytes) {
    for (OctantRecord& r : records) {
        const std::uint64_t at = r.at(), n = r.bytes();
        YV_CHECK(at + n <= bytes.size() && n <= kChunkBytes);
        if (chunks_.empty() || chunks_.back().size() + n > kChunkBytes) {
            chunks_.emplace_back();
            chunks_.back().reserve(kChunkBytes);
        }
        ByteVector& chunk = chunks_.back();
        const std::uint64_t place = (chunks_.size() - 1) * kChunkBytes + chunk.size();
        chunk.insert(chunk.end(), bytes.begin() + std::ptrdiff_t(at), bytes.begin() + std::ptrdiff_t(at + n));
        r.place = place << 16 | n;
    }
}

std::span<const std::uint8_t> OctantMemory::bytes(const OctantRecord& r) const {
    const std::uint64_t chunk = r.at() / kChunkBytes, at = r.at() % kChunkBytes;
    if (chunk >= chunks_.size() || at + r.bytes() > chunks_[chunk].size())
        throw Error("level-of-detail record beyond the bytes kept for it");
    return std::span<const std::uint8_t>(chunks_[chunk]).subspan(at, r.bytes());
}

} // namespace yv

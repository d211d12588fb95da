#include "vdb/leaf_records.h"

#include "core/error.h"

#include <openvdb/Types.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

namespace yv {
namespace {

std::string leafWhere(const VdbIndex& index, const VdbGridInfo& grid, std::size_t leaf, glm::ivec3 brick,
                      std::uint64_t recordAt) {
    const glm::ivec3 v = brick * 8;
    return index.path() + ": byte " + std::to_string(recordAt) + ": grid '" + grid.name + "', leaf " +
           std::to_string(leaf) + " at voxel (" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " +
           std::to_string(v.z) + ")";
}

} // namespace

void readLeafRecords(const VdbIndex& index, const VdbGridInfo& grid, const VdbLeafTable& table, std::size_t first,
                     std::size_t last, std::vector<std::uint8_t>& bytes) {
    YV_CHECK(first <= last && last < table.records.size());
    bytes.resize(std::size_t(table.records[last] - table.records[first]));
    index.file().read(table.records[first], bytes, "grid '" + grid.name + "' leaves " + std::to_string(first) + " to " +
                                                       std::to_string(last - 1));
}

void decodeLeafRecord(std::span<const std::uint8_t> record, const VdbIndex& index, const VdbGridInfo& grid,
                      std::size_t leaf, glm::ivec3 brick, std::uint64_t recordAt, float* out,
                      std::uint64_t* activeOut) {
    const std::size_t components = grid.vector ? 3 : 1;
    const std::size_t valueBytes = grid.half ? 2 : 4;
    std::uint64_t words[8];
    if (record.size() <= sizeof words)
        throw Error(leafWhere(index, grid, leaf, brick, recordAt) + ": a record of " + std::to_string(record.size()) +
                    " bytes, shorter than its mask (damaged)");
    std::memcpy(words, record.data(), sizeof words);
    if (activeOut) std::memcpy(activeOut, words, sizeof words);
    std::size_t active = 0;
    for (std::uint64_t w : words) active += std::size_t(std::popcount(w));
    if (record.size() != sizeof words + 1 + active * components * valueBytes || record[sizeof words] != 0)
        throw Error(leafWhere(index, grid, leaf, brick, recordAt) + ": the record's mask or layout differs from the topology (damaged)");
    std::fill(out, out + 512 * components, 0.0f);
    const std::uint8_t* p = record.data() + sizeof words + 1;
    for (int w = 0; w < 8; ++w)
        for (std::uint64_t bits = words[w]; bits; bits &= bits - 1) {
            float* v = out + std::size_t(w * 64 + std::countr_zero(bits)) * components;
            for (std::size_t c = 0; c < components; ++c, p += valueBytes) {
                if (grid.half) {
                    openvdb::math::half h;
                    std::memcpy(&h, p, 2);
                    v[c] = float(h);
                } else {
                    std::memcpy(&v[c], p, 4);
                }
                if (!std::isfinite(v[c]))
                    throw Error(leafWhere(index, grid, leaf, brick, recordAt) + ": voxel " +
                                std::to_string(w * 64 + std::countr_zero(bits)) + " holds " + std::to_string(v[c]) +
                                ", not a finite value (damaged)");
            }
        }
}

} // namespace yv

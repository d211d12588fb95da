#include "vdb/leaf_records.h"

#include "core/brick_mask.h"
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

namespace {

/// One stored value as a float.
template <bool Half> float loadValue(const std::uint8_t* p) {
    if constexpr (Half) {
        openvdb::math::half h;
        std::memcpy(&h, p, 2);
        return float(h);
    } else {
        float f;
        std::memcpy(&f, p, 4);
        return f;
    }
}

/// Scatters the active values of one record into `out`. The hot loop of
/// every read of a volume: no branch on the grid's kind inside, a whole
/// word of active voxels copied as a run, and finiteness gathered as a flag
/// (the caller looks for the voxel only when it is false).
template <bool Half, int Components>
bool scatterValues(const std::uint64_t (&words)[8], const std::uint8_t* p, float* out) {
    constexpr std::size_t kStep = (Half ? 2 : 4) * Components;
    bool finite = true;
    for (int w = 0; w < 8; ++w) {
        if (words[w] == ~std::uint64_t(0)) {
            float* v = out + std::size_t(w * 64) * Components;
            for (int i = 0; i < 64 * Components; ++i, p += kStep / Components) {
                v[i] = loadValue<Half>(p);
                finite &= std::isfinite(v[i]);
            }
            continue;
        }
        for (std::uint64_t bits = words[w]; bits; bits &= bits - 1, p += kStep) {
            float* v = out + std::size_t(w * 64 + std::countr_zero(bits)) * Components;
            for (int c = 0; c < Components; ++c) {
                v[c] = loadValue<Half>(p + c * (kStep / Components));
                finite &= std::isfinite(v[c]);
            }
        }
    }
    return finite;
}

} // namespace

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
    const std::size_t active = std::size_t(activeVoxelCount(words));
    if (record.size() != sizeof words + 1 + active * components * valueBytes || record[sizeof words] != 0)
        throw Error(leafWhere(index, grid, leaf, brick, recordAt) + ": the record's mask or layout differs from the topology (damaged)");
    std::fill(out, out + 512 * components, 0.0f);
    const std::uint8_t* p = record.data() + sizeof words + 1;
    const bool finite = grid.half ? (grid.vector ? scatterValues<true, 3>(words, p, out) : scatterValues<true, 1>(words, p, out))
                                  : (grid.vector ? scatterValues<false, 3>(words, p, out) : scatterValues<false, 1>(words, p, out));
    if (finite) return;
    for (int v = 0; v < 512; ++v)
        for (std::size_t c = 0; c < components; ++c)
            if (const float x = out[std::size_t(v) * components + c]; !std::isfinite(x))
                throw Error(leafWhere(index, grid, leaf, brick, recordAt) + ": voxel " + std::to_string(v) + " holds " +
                            std::to_string(x) + ", not a finite value (damaged)");
}

} // namespace yv

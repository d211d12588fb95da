#include "vdb/leaf_batches.h"

#include "core/error.h"
#include "vdb/lod_pyramid.h"
#include "vdb/tree_order.h"

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <bit>
#include <limits>
#include <span>
#include <tuple>
#include <utility>

namespace yv {
namespace {

/// Bricks are encoded in pieces of this many, so a large region never holds
/// all of its encoded bytes at once.
constexpr std::size_t kEncodePiece = 4096;
/// Leaves per write into the scratch file (encodeBatch): about 0.5 to 2 MB.
constexpr std::size_t kSpillBlock = 256;

/// The bounds of a brick's active voxels (voxel v = x 64 + y 8 + z: word x
/// of the mask, byte y of the word, bit z of the byte), from its mask alone.
openvdb::CoordBBox activeBounds(std::uint64_t key, const BrickMask& mask) {
    int xMin = -1, xMax = -1;
    std::uint64_t yz = 0;
    for (int w = 0; w < kBrickVoxels / 64; ++w)
        if (mask[w]) {
            if (xMin < 0) xMin = w;
            xMax = w;
            yz |= mask[w];
        }
    if (xMin < 0) return {};
    int yMin = 8, yMax = -1;
    unsigned z = 0;
    for (int y = 0; y < 8; ++y)
        if (const unsigned byte = unsigned(yz >> (8 * y)) & 0xffu) {
            yMin = std::min(yMin, y);
            yMax = y;
            z |= byte;
        }
    const glm::ivec3 o = brickCoord(key) * kBrickSize;
    return {openvdb::Coord(o.x + xMin, o.y + yMin, o.z + std::countr_zero(z)),
            openvdb::Coord(o.x + xMax, o.y + yMax, o.z + 31 - std::countl_zero(z))};
}

} // namespace

template <typename Batch>
EncodedBatch encodeBatch(const PyramidLevel& level, SpillFile& spill, const Batch& bricks, OctantOutput octants) {
    // In tree order within the batch: the write then reads runs of neighbours with one call.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> order(bricks.size());
    for (std::size_t i = 0; i < bricks.size(); ++i) order[i] = {treeOrderKey(brickCoord(bricks.key(i))), std::uint32_t(i)};
    std::sort(order.begin(), order.end());

    EncodedBatch batch;
    batch.records.resize(bricks.size());
    for (std::size_t first = 0; first < bricks.size(); first += kEncodePiece) {
        const std::size_t count = std::min(kEncodePiece, bricks.size() - first);
        // Per grid, then the octants.
        constexpr int kOctants = kMaxGrids;
        std::vector<ByteVector> encoded[kMaxGrids + 1];
        for (auto& e : encoded) e.resize(count);
        std::vector<openvdb::CoordBBox> pieceBounds(count);
        std::vector<std::uint32_t> activeCounts(count);
        // Level 0's statistics, of the values as stored (exact sums: any order gives the same bits).
        const bool counted = level.number == 0;
        const bool half = level.encoding[0].half;
        tbb::combinable<VoxelStatistics> statistics;
        tbb::parallel_for(std::size_t(0), count, [&](std::size_t i) {
            const std::size_t b = order[first + i].second;
            LeafRecord& r = batch.records[first + i];
            r.mask = bricks.mask(b);
            for (int g = 0; g < level.gridCount; ++g) r.load[g] = bricks.encode(*level.encoders[g], b, r.mask, encoded[g][i]);
            if (octants.skip) bricks.octant(b, r.mask, octants.skip, encoded[kOctants][i]);
            pieceBounds[i] = activeBounds(bricks.key(b), r.mask);
            activeCounts[i] += std::uint32_t(activeVoxelCount(r.mask));
            if (counted) bricks.count(b, r.mask, half, statistics.local());
        });
        statistics.combine_each([&](const VoxelStatistics& s) { batch.statistics += s; });
        // Each grid's piece (and the octants) in one range of the scratch
        // file, written in blocks on every core: joined and written by one
        // thread, a region's pieces were most of its encode time.
        // Octants kept in memory are joined into the batch's bytes instead.
        const bool spillOctants = octants.skip && !octants.inMemory;
        std::vector<std::uint64_t> blockAt[kMaxGrids + 1]; // where each block of kSpillBlock leaves goes
        for (int g = 0; g <= kOctants; ++g) {
            if (g == kOctants ? !octants.skip : g >= level.gridCount) continue;
            std::uint64_t at = 0;
            for (std::size_t i = 0; i < count; ++i) at += encoded[g][i].size();
            at = g == kOctants && !spillOctants ? batch.octantBytes.size() : spill.reserve(at);
            for (std::size_t i = 0; i < count; ++i) {
                if (i % kSpillBlock == 0) blockAt[g].push_back(at);
                LeafRecord& r = batch.records[first + i];
                if (g == kOctants) {
                    YV_CHECK(encoded[g][i].size() < 0x10000);
                    batch.octants.push_back({bricks.key(order[first + i].second), at << 16 | encoded[g][i].size()});
                    if (!spillOctants)
                        batch.octantBytes.insert(batch.octantBytes.end(), encoded[g][i].begin(), encoded[g][i].end());
                } else {
                    r.at[g] = at;
                    r.bytes[g] = std::uint32_t(encoded[g][i].size());
                }
                at += encoded[g][i].size();
            }
        }
        const std::size_t blocks = (count + kSpillBlock - 1) / kSpillBlock;
        tbb::parallel_for(std::size_t(0), std::size_t(kOctants + 1) * blocks, [&](std::size_t task) {
            const int g = int(task / blocks);
            if (g == kOctants ? !spillOctants : g >= level.gridCount) return;
            const std::size_t block = task % blocks, begin = block * kSpillBlock, end = std::min(count, begin + kSpillBlock);
            ByteVector joined;
            for (std::size_t i = begin; i < end; ++i) joined.insert(joined.end(), encoded[g][i].begin(), encoded[g][i].end());
            spill.writeAt(blockAt[g][block], joined);
        });
        for (std::size_t i = 0; i < count; ++i) {
            batch.records[first + i].order = order[first + i].first;
            batch.activeVoxels += activeCounts[i];
            if (!pieceBounds[i].empty()) batch.bounds.expand(pieceBounds[i]);
        }
    }
    return batch;
}

void addBatch(PyramidLevel& level, EncodedBatch&& batch, std::uint32_t source) {
    for (LeafRecord& r : batch.records) r.source = source;
    level.leaves.insert(level.leaves.end(), batch.records.begin(), batch.records.end());
    if (!batch.bounds.empty()) level.activeBounds.expand(batch.bounds);
    level.activeVoxels += batch.activeVoxels;
    level.statistics += batch.statistics;
}

void appendInTreeOrder(std::span<const std::span<const LeafRecord>> pieces, std::vector<LeafRecord>& leaves) {
    std::size_t count = 0;
    for (std::span<const LeafRecord> piece : pieces) count += piece.size();
    const std::size_t first = leaves.size();
    // Below this the records' own sort is as fast.
    constexpr std::size_t kKeySortFrom = 4096;
    if (count < kKeySortFrom) {
        for (std::span<const LeafRecord> piece : pieces) leaves.insert(leaves.end(), piece.begin(), piece.end());
        std::stable_sort(leaves.begin() + std::ptrdiff_t(first), leaves.end(), inTreeOrder);
        return;
    }
    // A record's key and where it lies: ties go by piece, then place in it.
    struct Key {
        std::uint64_t order;
        std::uint32_t source, piece, place;
        bool operator<(const Key& o) const {
            return std::tie(order, source, piece, place) < std::tie(o.order, o.source, o.piece, o.place);
        }
    };
    YV_CHECK(pieces.size() <= std::numeric_limits<std::uint32_t>::max());
    std::vector<Key> keys(count);
    std::size_t at = 0;
    for (std::size_t p = 0; p < pieces.size(); ++p) {
        const std::span<const LeafRecord> piece = pieces[p];
        YV_CHECK(piece.size() <= std::numeric_limits<std::uint32_t>::max());
        tbb::parallel_for(std::size_t(0), piece.size(), [&, at](std::size_t i) {
            keys[at + i] = {piece[i].order, piece[i].source, std::uint32_t(p), std::uint32_t(i)};
        });
        at += piece.size();
    }
    tbb::parallel_sort(keys.begin(), keys.end());
    leaves.resize(first + count);
    tbb::parallel_for(std::size_t(0), count, [&](std::size_t i) {
        leaves[first + i] = pieces[keys[i].piece][keys[i].place];
    });
}

void sortInTreeOrder(std::vector<LeafRecord>& leaves) {
    std::vector<LeafRecord> sorted;
    sorted.reserve(leaves.size());
    const std::span<const LeafRecord> all(leaves);
    appendInTreeOrder(std::span(&all, 1), sorted);
    leaves.swap(sorted);
}

template EncodedBatch encodeBatch(const PyramidLevel&, SpillFile&, const VoxelBrickBatch&, OctantOutput);
template EncodedBatch encodeBatch(const PyramidLevel&, SpillFile&, const PackedBrickBatch&, OctantOutput);

} // namespace yv

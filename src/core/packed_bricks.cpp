#include "core/packed_bricks.h"

#include "core/error.h"
#include "core/parallel_copy.h"
#include "core/trace.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <limits>
#include <string>

namespace yv {

namespace {

/// Makes room for `count` records in `v` without a copy on one thread: a
/// larger storage (at least half as large again) is filled on every core.
template <typename T>
void growTo(PackedBricks::Storage<T>& v, std::size_t count) {
    if (count <= v.capacity()) {
        v.resize(count, boost::container::default_init);
        return;
    }
    PackedBricks::Storage<T> bigger;
    bigger.reserve(std::max(count, v.capacity() + v.capacity() / 2));
    bigger.resize(count, boost::container::default_init);
    copyInParallel(bigger.data(), v.data(), v.size() * sizeof(T));
    v.swap(bigger);
}

} // namespace

void PackedBricks::append(const PackedBrickHeader* h, std::size_t brickCount, const PackedVoxel* v,
                          std::size_t voxelCount, const PackedAlbedo* a) {
    // firstVoxel is 32 bits: a region (at most 1024^3 voxels) always fits.
    YV_CHECK(voxels.size() + voxelCount <= std::numeric_limits<std::uint32_t>::max());
    // Colour for every voxel or for none: a mix would pair voxels with others' colours.
    YV_CHECK(a ? albedo.size() == voxels.size() : albedo.empty());
    const auto shift = static_cast<std::uint32_t>(voxels.size());
    const std::size_t firstBrick = headers.size(), firstVoxel = voxels.size();
    {
        const TraceSpan span("grow the packed bricks");
        growTo(headers, firstBrick + brickCount);
        growTo(voxels, firstVoxel + voxelCount);
        if (a) growTo(albedo, firstVoxel + voxelCount);
    }
    const TraceSpan span("copy the packed bricks");
    copyInParallel(headers.data() + firstBrick, h, brickCount * sizeof(PackedBrickHeader));
    copyInParallel(voxels.data() + firstVoxel, v, voxelCount * sizeof(PackedVoxel));
    if (a) copyInParallel(albedo.data() + firstVoxel, a, voxelCount * sizeof(PackedAlbedo));
    for (std::size_t i = firstBrick; i < headers.size(); ++i) headers[i].firstVoxel += shift;
}

ResolveTally tallyOf(const PackedBrickHeader& h) {
    ResolveTally t;
    t.activeVoxels = h.activeCount;
    t.voxelsOverOne = h.voxelsOverOne;
    t.densitySum = h.densitySum;
    t.rawDensitySum = h.rawDensitySum;
    t.excessOverOne = h.excessOverOne;
    return t;
}

std::array<std::uint64_t, kBrickVoxels / 64> packedBrickMask(const PackedBricks& packed, std::size_t i) {
    const PackedBrickHeader& h = packed.headers[i];
    std::array<std::uint64_t, kBrickVoxels / 64> mask;
    int count = 0;
    for (int w = 0; w < kBrickVoxels / 64; ++w) {
        mask[w] = std::uint64_t(h.activeMask[2 * w]) | (std::uint64_t(h.activeMask[2 * w + 1]) << 32);
        count += std::popcount(mask[w]);
    }
    if (count != int(h.activeCount) || count == 0 || std::uint64_t(h.firstVoxel) + count > packed.voxels.size())
        throw Error("packed brick " + std::to_string(h.brickKey()) + ": " + std::to_string(h.activeCount) +
                    " active voxels from " + std::to_string(h.firstVoxel) + ", mask has " + std::to_string(count) +
                    ", " + std::to_string(packed.voxels.size()) + " voxels held");
    return mask;
}

void unpackBrick(const PackedBricks& packed, std::size_t i, VoxelBrick& out) {
    const PackedBrickHeader& h = packed.headers[i];
    out.key = h.brickKey();
    out.activeMask = packedBrickMask(packed, i);
    out.density.fill(0.0f);
    out.orientation.fill(glm::vec3(0.0f));
    const bool withAlbedo = !packed.albedo.empty();
    if (withAlbedo && packed.albedo.size() != packed.voxels.size())
        throw Error("packed bricks: " + std::to_string(packed.albedo.size()) + " colours for " +
                    std::to_string(packed.voxels.size()) + " voxels");
    if (withAlbedo)
        out.albedo.assign(kBrickVoxels, glm::vec3(0.0f));
    else
        out.albedo.clear();
    const PackedVoxel* v = packed.voxels.data() + h.firstVoxel;
    const PackedAlbedo* a = withAlbedo ? packed.albedo.data() + h.firstVoxel : nullptr;
    for (int w = 0; w < kBrickVoxels / 64; ++w)
        for (std::uint64_t bits = out.activeMask[w]; bits; bits &= bits - 1, ++v) {
            const int offset = w * 64 + std::countr_zero(bits);
            out.density[offset] = v->density;
            out.orientation[offset] = glm::vec3(v->axis[0], v->axis[1], v->axis[2]);
            if (a) {
                out.albedo[offset] = glm::vec3(a->rgb[0], a->rgb[1], a->rgb[2]);
                ++a;
            }
        }
}

std::vector<VoxelBrick> unpackBricks(const PackedBricks& packed, ResolveTally* tally) {
    std::vector<VoxelBrick> bricks(packed.headers.size());
    tbb::parallel_for(std::size_t(0), bricks.size(), [&](std::size_t i) { unpackBrick(packed, i, bricks[i]); });
    if (tally)
        for (const PackedBrickHeader& h : packed.headers) *tally += tallyOf(h);
    return bricks;
}

BrickVolume unpackVolume(const VoxelGrid& grid, Reduce reduce, const std::vector<PackedBricks>& regions) {
    struct Ref {
        std::uint64_t key;
        std::uint32_t region, index;
    };
    std::vector<Ref> order;
    for (std::size_t r = 0; r < regions.size(); ++r)
        for (std::size_t i = 0; i < regions[r].headers.size(); ++i)
            order.push_back({regions[r].headers[i].brickKey(), std::uint32_t(r), std::uint32_t(i)});
    tbb::parallel_sort(order.begin(), order.end(), [](const Ref& a, const Ref& b) { return a.key < b.key; });
    BrickVolume volume;
    volume.grid = grid;
    volume.reduce = reduce;
    volume.bricks.resize(order.size());
    tbb::parallel_for(std::size_t(0), order.size(), [&](std::size_t i) {
        unpackBrick(regions[order[i].region], order[i].index, volume.bricks[i]);
    });
    for (const Ref& ref : order) volume.tally += tallyOf(regions[ref.region].headers[ref.index]);
    return volume;
}

} // namespace yv

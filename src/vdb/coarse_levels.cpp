#include "vdb/coarse_levels.h"

#include "core/error.h"
#include "core/trace.h"
#include "vdb/lod_pyramid.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <memory>

namespace yv {
namespace {

/// Coarse bricks are built in pieces of this many, so a level never holds
/// more than a piece of resolved bricks (about 8 MB).
constexpr std::size_t kPyramidPiece = 1024;

} // namespace

std::span<const std::uint8_t> OctantSource::bytes(const OctantRecord& r, ByteVector& buffer) const {
    if (memory) return memory->bytes(r);
    buffer.resize(r.bytes());
    spill.read(r.at(), buffer);
    return buffer;
}

void buildLevel(PyramidLevel& level, int skip, const OctantSource& from, std::vector<OctantRecord>& octants,
                SpillFile& spill, std::vector<OctantRecord>* next) {
    const TraceSpan span("build a level of detail");
    tbb::parallel_sort(octants.begin(), octants.end(), [skip](const OctantRecord& a, const OctantRecord& b) {
        const std::uint64_t pa = parentBrickKey(a.childKey, skip), pb = parentBrickKey(b.childKey, skip);
        return pa != pb ? pa < pb : a.childKey < b.childKey;
    });
    std::vector<std::size_t> groups; // where each parent's octants start
    for (std::size_t i = 0; i < octants.size(); ++i)
        if (i == 0 || parentBrickKey(octants[i].childKey, skip) != parentBrickKey(octants[i - 1].childKey, skip))
            groups.push_back(i);
    groups.push_back(octants.size());
    const std::size_t parents = groups.size() - 1;

    tbb::enumerable_thread_specific<std::unique_ptr<CoarseBrick>> scratch;
    tbb::enumerable_thread_specific<ByteVector> buffers;
    std::vector<VoxelBrick> bricks;
    std::vector<ByteVector> nextOctants;
    std::vector<std::uint8_t> keep;
    for (std::size_t first = 0; first < parents; first += kPyramidPiece) {
        const std::size_t count = std::min(kPyramidPiece, parents - first);
        bricks.resize(count);
        keep.assign(count, 0);
        nextOctants.assign(next ? count : 0, ByteVector());
        tbb::parallel_for(std::size_t(0), count, [&](std::size_t i) {
            std::unique_ptr<CoarseBrick>& sums = scratch.local();
            if (!sums) sums = std::make_unique<CoarseBrick>();
            ByteVector& buffer = buffers.local();
            const std::size_t g = first + i;
            sums->clear(parentBrickKey(octants[groups[g]].childKey, skip), level.gridCount > 2, skip);
            for (std::size_t k = groups[g]; k < groups[g + 1]; ++k)
                placeOctant(from.bytes(octants[k], buffer), octants[k].childKey, *sums);
            keep[i] = resolveCoarseBrick(*sums, bricks[i]);
            if (next && keep[i]) appendOctant(*sums, bricks[i], nextOctants[i]);
        });
        if (next) {
            ByteVector joined;
            for (std::size_t i = 0; i < count; ++i) joined.insert(joined.end(), nextOctants[i].begin(), nextOctants[i].end());
            std::uint64_t at = spill.append(joined);
            for (std::size_t i = 0; i < count; ++i) {
                if (!keep[i]) continue;
                YV_CHECK(nextOctants[i].size() < 0x10000);
                next->push_back({bricks[i].key, at << 16 | nextOctants[i].size()});
                at += nextOctants[i].size();
            }
        }
        std::size_t kept = 0;
        for (std::size_t i = 0; i < count; ++i)
            if (keep[i]) {
                if (kept != i) bricks[kept] = bricks[i];
                ++kept;
            }
        addBatch(level, encodeBatch(level, spill, VoxelBrickBatch{std::span(bricks.data(), kept)}), 0);
    }
}

} // namespace yv

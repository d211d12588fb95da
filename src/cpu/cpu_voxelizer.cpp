#include "cpu/cpu_voxelizer.h"

#include "core/error.h"
#include "core/progress.h"
#include "cpu/slice_sampler.h"
#include "garment/slice_measures.h"
#include "plan/grid.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <numeric>
#include <unordered_map>

namespace yv {
namespace {

/// One thread's bricks: a hash from brick key to a slot in `bricks`.
struct ThreadBricks {
    std::unordered_map<std::uint64_t, std::uint32_t> slotOf;
    std::vector<BrickAccumulator> bricks;
    std::uint64_t lastKey = ~std::uint64_t(0);
    std::uint32_t lastSlot = 0;
    std::uint64_t samples = 0;

    std::uint32_t* words(std::uint64_t key, Reduce reduce, bool albedo) {
        if (key != lastKey) {
            auto [it, inserted] = slotOf.try_emplace(key, static_cast<std::uint32_t>(bricks.size()));
            if (inserted)
                bricks.push_back({key, std::vector<std::uint32_t>(wordsPerVoxel(reduce, albedo) * kBrickVoxels, 0)});
            lastKey = key;
            lastSlot = it->second;
        }
        return bricks[lastSlot].words.data();
    }
};

/// The box's voxels, whose samples a box's pass computes. A side of the box
/// on the grid's face is left open, so that a sample beyond the grid is
/// still met there, and refused.
SampleWindow windowOf(const VoxelGrid& grid, glm::ivec3 boxMin, glm::ivec3 boxMax) {
    SampleWindow window;
    for (int a = 0; a < 3; ++a) {
        if (boxMin[a] > 0) window.min[a] = boxMin[a];
        if (boxMax[a] < grid.dims[a]) window.max[a] = boxMax[a];
    }
    return window;
}

/// The numbers (see accumulateBox's `first`) of the slices of `segments`
/// whose samples can reach `window`, ascending, placed and tested on every
/// core: the slice's centre and its segment's reach, as the zoom planner
/// bins segments, plus a voxel.
std::vector<std::uint64_t> slicesReaching(const SlicePlan& plan, const VoxelGrid& grid,
                                          std::span<const std::uint32_t> segments,
                                          const std::vector<std::uint64_t>& first, const SampleWindow& window) {
    const double invH = 1.0 / grid.voxelSize;
    const auto reachesWindow = [&](const glm::dvec3& centre, const SegmentRecord& seg) {
        const glm::dvec3 c = (centre - grid.origin) * invH;
        const double reach = seg.reach * invH + kSampleReachVoxels + 2.0;
        for (int a = 0; a < 3; ++a)
            if (c[a] + reach <= double(window.min[a]) || c[a] - reach >= double(window.max[a])) return false;
        return true;
    };
    const std::uint64_t sliceCount = first.back();
    std::vector<std::uint8_t> reaches(sliceCount);
    tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, sliceCount, 256), [&](const tbb::blocked_range<std::uint64_t>& range) {
        // The centres of a segment's slices in the range, several at a time
        // (sliceAxes: no frame, which the test does not need).
        std::size_t i = std::upper_bound(first.begin(), first.end(), range.begin()) - first.begin() - 1;
        constexpr std::uint64_t kChunk = 64;
        SliceAxis chunk[kChunk];
        for (std::uint64_t n = range.begin(); n != range.end();) {
            while (n >= first[i + 1]) ++i;
            const SegmentRecord& seg = plan.segments[segments[i]];
            const std::uint64_t count = std::min({kChunk, range.end() - n, first[i + 1] - n});
            sliceAxes(seg, static_cast<std::uint32_t>(n - first[i]), static_cast<std::uint32_t>(count), chunk);
            for (std::uint64_t j = 0; j < count; ++j) reaches[n + j] = reachesWindow(chunk[j].centre, seg);
            n += count;
        }
    });
    std::vector<std::uint64_t> out;
    for (std::uint64_t n = 0; n < sliceCount; ++n)
        if (reaches[n]) out.push_back(n);
    return out;
}

} // namespace

CpuVoxelizeCounters& CpuVoxelizeCounters::operator+=(const CpuVoxelizeCounters& o) {
    samples += o.samples;
    tasks += o.tasks;
    threads = std::max(threads, o.threads);
    slicesSampled += o.slicesSampled;
    busyBoxThreadsMin = std::min(busyBoxThreadsMin, o.busyBoxThreadsMin);
    return *this;
}

void accumulateSample(Reduce reduce, std::uint32_t* words, int v, double volumeFraction, float density,
                      const glm::dvec3& direction, const glm::dvec3* albedo) {
    if (reduce == Reduce::Mean) {
        const glm::dvec3& o = direction;
        words[v] += toFixed(volumeFraction);
        const double terms[6] = {o.x * o.x, o.y * o.y, o.z * o.z, o.x * o.y, o.x * o.z, o.y * o.z};
        for (int i = 0; i < 6; ++i)
            words[(1 + i) * kBrickVoxels + v] += static_cast<std::uint32_t>(toFixedSigned(volumeFraction * terms[i]));
        if (albedo)
            for (int i = 0; i < 3; ++i) words[(kMeanWords + i) * kBrickVoxels + v] += toFixed(volumeFraction * (*albedo)[i]);
        return;
    }
    const std::uint32_t d = floatBits(density), code = encodeAxis(direction);
    if (d > words[v] || (d == words[v] && code > words[kBrickVoxels + v])) {
        words[v] = d;
        words[kBrickVoxels + v] = code;
    }
}

std::vector<BrickAccumulator> accumulateBox(const SlicePlan& plan, const CrossSection& xs, const VoxelGrid& grid,
                                            const VoxelizeSettings& settings, std::span<const std::uint32_t> segments,
                                            glm::ivec3 boxMin, glm::ivec3 boxMax, CpuVoxelizeCounters* counters) {
    checkSupersample(settings.supersample);
    // A --bbox run's voxels outside its box get no sample (the others keep every one they had).
    if (settings.clip) {
        const VoxelBox kept = intersect({boxMin, boxMax}, *settings.clip);
        boxMin = kept.min;
        boxMax = glm::max(kept.max, kept.min);
    }
    const Reduce reduce = settings.reduce;
    const bool albedo = xs.hasAlbedo();
    if (albedo && reduce != Reduce::Mean)
        throw Error("--albedo needs --reduce mean (a colour is averaged like the density, not maxed)");
    const double radius = plan.options.radius;
    const double support = textureSupport(xs);
    tbb::enumerable_thread_specific<ThreadBricks> perThread;
    // The box's slices numbered one after another across its segments
    // (first[i]: the number of segment i's first slice), so that the work
    // splits by slice: a region crossed by a few long segments still keeps
    // every core busy.
    std::vector<std::uint64_t> first(segments.size() + 1, 0);
    for (std::size_t i = 0; i < segments.size(); ++i) first[i + 1] = first[i] + plan.segments[segments[i]].sliceCount;
    std::atomic<bool> outside{false};
    std::atomic<std::uint64_t> tasks{0};

    // The slices that can reach the box are sampled a few a task: the work
    // splits by what is sampled, so a small region's few slices still go to
    // every core. Their order is the plan's, and consecutive slices are
    // close in space, so each task touches few bricks.
    const SampleWindow window = windowOf(grid, boxMin, boxMax);
    const std::vector<std::uint64_t> toSample = slicesReaching(plan, grid, segments, first, window);
    const auto segmentOf = [&](std::uint64_t n) {
        return std::size_t(std::upper_bound(first.begin(), first.end(), n) - first.begin() - 1);
    };
    Progress progress("voxelize", toSample.size(), settings.quiet, "slices");
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, toSample.size(), 2), [&](const tbb::blocked_range<std::size_t>& range) {
        ThreadBricks& local = perThread.local();
        for (std::size_t r = range.begin(), i = segmentOf(toSample[r]); r != range.end(); ++r) {
            const std::uint64_t n = toSample[r];
            while (n >= first[i + 1]) ++i;
            const SegmentRecord& seg = plan.segments[segments[i]];
            const Slice slice = placeSlice(seg, static_cast<std::uint32_t>(n - first[i]));
            sampleSlice(slice, radius, xs, support, grid, settings.supersample, window, [&](const SliceSample& smp) {
                const glm::ivec3 v = smp.voxel;
                if (glm::any(glm::lessThan(v, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(v, grid.dims))) {
                    outside = true;
                    return;
                }
                // Another box's voxel: that box's pass takes it.
                if (glm::any(glm::lessThan(v, boxMin)) || glm::any(glm::greaterThanEqual(v, boxMax))) return;
                std::uint32_t* w = local.words(brickKey(v >> 3), reduce, albedo);
                accumulateSample(reduce, w, brickOffset(v.x & 7, v.y & 7, v.z & 7), smp.volumeFraction, smp.density,
                                 smp.direction, albedo ? &smp.albedo : nullptr);
                ++local.samples;
            });
        }
        progress.advance(range.size());
        tasks.fetch_add(1, std::memory_order_relaxed);
    });
    const std::uint64_t slicesSampled = toSample.size();
    progress.finish();
    if (outside) throw Error("a slice sample fell outside the voxel grid (the grid does not contain the garment)");

    // Merge per-thread bricks: gather every key, then combine each brick's
    // copies in thread order. Integer sums and lexicographic max make the
    // result independent of which thread saw which slice.
    std::vector<ThreadBricks*> threads;
    std::uint64_t samples = 0;
    for (ThreadBricks& t : perThread) {
        threads.push_back(&t);
        samples += t.samples;
    }
    std::vector<std::uint64_t> keys;
    for (ThreadBricks* t : threads)
        for (const BrickAccumulator& b : t->bricks) keys.push_back(b.key);
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());

    std::vector<BrickAccumulator> merged(keys.size());
    tbb::parallel_for(std::size_t(0), keys.size(), [&](std::size_t i) {
        BrickAccumulator& out = merged[i];
        out.key = keys[i];
        for (ThreadBricks* t : threads) {
            auto it = t->slotOf.find(keys[i]);
            if (it == t->slotOf.end()) continue;
            std::vector<std::uint32_t>& words = t->bricks[it->second].words;
            if (out.words.empty())
                out.words = std::move(words);
            else
                combineAccumulators(reduce, out.words.data(), words.data(), albedo);
        }
    });
    if (counters) {
        counters->samples += samples;
        counters->tasks += tasks;
        counters->slicesSampled += slicesSampled;
        counters->threads = std::max<std::uint64_t>(counters->threads, threads.size());
        // Boxes with fewer slices than threads cannot keep them all busy.
        if (slicesSampled >= 8 * std::uint64_t(tbb::this_task_arena::max_concurrency()))
            counters->busyBoxThreadsMin = std::min<std::uint64_t>(counters->busyBoxThreadsMin, threads.size());
    }
    return merged;
}

BrickVolume voxelizeCpu(const SlicePlan& plan, const CrossSection& xs, const VoxelGrid& grid,
                        const VoxelizeSettings& settings, CpuVoxelizeCounters* counters) {
    std::vector<std::uint32_t> all(plan.segments.size());
    std::iota(all.begin(), all.end(), 0u);
    std::vector<BrickAccumulator> accumulators = accumulateBox(plan, xs, grid, settings, all, glm::ivec3(0), grid.dims, counters);
    return resolveVolume(grid, settings.reduce, settings.overlap, accumulators);
}

} // namespace yv

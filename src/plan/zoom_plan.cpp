#include "plan/zoom_plan.h"

#include "core/error.h"
#include "core/sampling.h"
#include "core/trace.h"
#include "garment/slice_measures.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <iterator>
#include <memory>
#include <utility>

namespace yv {

void segmentVoxelBounds(const SlicePlan& plan, const VoxelGrid& grid, std::uint32_t segment, glm::dvec3& lo,
                        glm::dvec3& hi) {
    const SegmentRecord& seg = plan.segments[segment];
    const double invH = 1.0 / grid.voxelSize;
    const double reach = seg.reach * invH + kSampleReachVoxels + 1.0;
    lo = (seg.centerMin - grid.origin) * invH - reach;
    hi = (seg.centerMax - grid.origin) * invH + reach;
}

SegmentVoxelBox segmentVoxelBox(const SlicePlan& plan, const VoxelGrid& grid, std::uint32_t segment) {
    glm::dvec3 lo, hi;
    segmentVoxelBounds(plan, grid, segment, lo, hi);
    // lo < m for a whole m exactly when floor(lo) < m, hi > m when ceil(hi) > m;
    // clamped far beyond any grid (2^24 voxels an axis), so no int overflows.
    constexpr double kFar = double(1 << 30);
    const auto whole = [&](const glm::dvec3& v) { return glm::ivec3(glm::clamp(v, glm::dvec3(-kFar), glm::dvec3(kFar))); };
    return {whole(glm::floor(lo)), whole(glm::ceil(hi))};
}

namespace {

/// The `from` whose `reaches(s)`; long lists (the whole garment, near the top
/// of the split) tested in blocks on every core, and the blocks joined in
/// order: the same list.
template <class Reaches>
std::vector<std::uint32_t> filterSegments(const std::vector<std::uint32_t>& from, Reaches&& reaches) {
    constexpr std::size_t kBlock = 1 << 14;
    std::vector<std::uint32_t> out;
    if (from.size() <= kBlock) {
        for (std::uint32_t s : from)
            if (reaches(s)) out.push_back(s);
        return out;
    }
    std::vector<std::vector<std::uint32_t>> blocks((from.size() + kBlock - 1) / kBlock);
    tbb::parallel_for(std::size_t(0), blocks.size(), [&](std::size_t b) {
        const std::size_t end = std::min(from.size(), (b + 1) * kBlock);
        for (std::size_t i = b * kBlock; i < end; ++i)
            if (reaches(from[i])) blocks[b].push_back(from[i]);
    });
    std::size_t total = 0;
    for (const auto& block : blocks) total += block.size();
    out.reserve(total);
    for (const auto& block : blocks) out.insert(out.end(), block.begin(), block.end());
    return out;
}

} // namespace

std::vector<std::uint32_t> segmentsReaching(const SlicePlan& plan, const VoxelGrid& grid,
                                            const std::vector<std::uint32_t>& from, glm::ivec3 min, glm::ivec3 max) {
    return filterSegments(from, [&](std::uint32_t s) { return segmentVoxelBox(plan, grid, s).reaches(min, max); });
}

namespace {

/// Expected fragments per cell of `cell`^3 voxels, over the cells that
/// cover `over` (the grid, or a --bbox run's box: a box at a resolution the
/// whole grid's map would not fit in memory gets a map of its own size).
class HeatMap {
  public:
    HeatMap(VoxelBox over, int cell, bool dropOutside)
        : cell_(cell), first_(over.min / cell), dims_((over.max + cell - 1) / cell - first_), dropOutside_(dropOutside) {
        cells_ = std::make_unique<std::atomic<std::uint64_t>[]>(std::size_t(dims_.x) * dims_.y * dims_.z);
    }
    /// Fragments are kept in 1/1024ths: at coarse resolutions a slice
    /// expects less than one fragment, which rounded to whole ones was none.
    static std::uint64_t units(double fragments) { return static_cast<std::uint64_t>(fragments * kUnits + 0.5); }
    /// Adds `units` (units() of a slice's fragments, or a sum of them: whole
    /// numbers, so any order gives the same map) at `voxel`'s cell. A slice
    /// centred outside a box's map adds nothing (only its edge can reach the
    /// box); in the grid's map it goes to the nearest cell.
    void addUnits(glm::ivec3 voxel, std::uint64_t units) {
        glm::ivec3 c = cellOf(voxel);
        const bool outside = glm::any(glm::lessThan(c, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(c, dims_));
        if (outside && dropOutside_) return;
        c = glm::clamp(c, glm::ivec3(0), dims_ - 1);
        cells_[index(c)].fetch_add(units, std::memory_order_relaxed);
    }
    /// The map's cell holding `voxel`, before any clamping: the same for two
    /// voxels that add to the same cell, and (the map being monotonic) for
    /// every voxel between them.
    glm::ivec3 cellOf(glm::ivec3 voxel) const { return voxel / cell_ - first_; }
    /// Estimated fragments in voxels [min, max) (within the map's box):
    /// whole cells summed, cut cells in proportion to the part of them inside.
    double sum(glm::ivec3 min, glm::ivec3 max) const {
        const glm::ivec3 c0 = min / cell_, c1 = glm::min((max + cell_ - 1) / cell_, first_ + dims_);
        double total = 0.0;
        for (int z = c0.z; z < c1.z; ++z)
            for (int y = c0.y; y < c1.y; ++y)
                for (int x = c0.x; x < c1.x; ++x) {
                    const std::uint64_t v = cells_[index(glm::ivec3(x, y, z) - first_)].load(std::memory_order_relaxed);
                    if (!v) continue;
                    const glm::ivec3 lo = glm::max(min, glm::ivec3(x, y, z) * cell_);
                    const glm::ivec3 hi = glm::min(max, glm::ivec3(x + 1, y + 1, z + 1) * cell_);
                    const glm::dvec3 part = glm::dvec3(hi - lo) / double(cell_);
                    total += v * part.x * part.y * part.z;
                }
        return total / kUnits;
    }
    std::uint64_t touched() const {
        std::uint64_t n = 0;
        for (std::size_t i = 0; i < std::size_t(dims_.x) * dims_.y * dims_.z; ++i) n += cells_[i].load() != 0;
        return n;
    }

  private:
    static constexpr double kUnits = 1024.0;
    std::size_t index(glm::ivec3 c) const { return (std::size_t(c.z) * dims_.y + c.y) * dims_.x + c.x; }
    int cell_;
    glm::ivec3 first_, dims_; ///< the map's first cell, and its cells along each axis
    bool dropOutside_;
    std::unique_ptr<std::atomic<std::uint64_t>[]> cells_;
};

/// Adds to `heat` the fragments expected of each slice of the `segments`:
/// its square, projected on the face of its dominant axis, in supersampled
/// pixels, times the cross-section's filled fraction, times the voxels each
/// sample's slab is split over (1 + its depth in voxels, on average over
/// where it starts; the slices' tangents taken at their segment's mean), at
/// the cell of its centre. A segment whose slice centres all lie in one
/// cell (its centres' bounds do) adds once; another finds each slice's
/// voxel from the curve's position alone. On every core; a segment whose
/// turn comes once `stopped()` adds nothing.
void addSliceHeat(HeatMap& heat, const SlicePlan& plan, const VoxelGrid& grid, const CrossSection& xs, int supersample,
                  const std::vector<std::uint32_t>& segments, const std::function<bool()>& stopped) {
    double filled = 0.0;
    for (std::uint8_t d : xs.density) filled += d != 0;
    filled /= double(xs.density.size());
    const double side = 2.0 * plan.options.radius / grid.voxelSize * supersample;
    const double perSlice = side * side * filled;
    const double invVoxelSize = 1.0 / grid.voxelSize;
    tbb::parallel_for(std::size_t(0), segments.size(), [&](std::size_t i) {
        if (stopped()) return;
        const SegmentRecord& seg = plan.segments[segments[i]];
        const double depth = seg.length / seg.sliceCount / grid.voxelSize;
        const std::uint64_t units = HeatMap::units(perSlice * (seg.meanDominant + depth));
        // The voxels of the centres' bounds bound the slices' (voxelHolding).
        const glm::ivec3 first = voxelHolding(seg.centerMin, grid.origin, invVoxelSize);
        if (heat.cellOf(first) == heat.cellOf(voxelHolding(seg.centerMax, grid.origin, invVoxelSize))) {
            heat.addUnits(first, units * seg.sliceCount);
            return;
        }
        // Consecutive slices mostly share a cell: the cell is found and
        // added to once a run.
        glm::ivec3 runVoxel(0);
        std::uint64_t runSlices = 0;
        constexpr std::uint32_t kChunk = 64;
        glm::ivec3 chunk[kChunk];
        for (std::uint32_t from = 0; from < seg.sliceCount; from += kChunk) {
            const std::uint32_t count = std::min(kChunk, seg.sliceCount - from);
            sliceVoxels(seg, from, count, grid.origin, invVoxelSize, chunk);
            for (std::uint32_t j = 0; j < count; ++j) {
                if (runSlices && heat.cellOf(chunk[j]) != heat.cellOf(runVoxel)) {
                    heat.addUnits(runVoxel, units * runSlices);
                    runSlices = 0;
                }
                if (!runSlices) runVoxel = chunk[j];
                ++runSlices;
            }
        }
        if (runSlices) heat.addUnits(runVoxel, units * runSlices);
    });
}

/// Split position along one axis: the middle, rounded to the coarsest
/// alignment that still leaves both halves non-empty.
int splitPoint(int lo, int hi) {
    for (int align : {128, 32, 8}) {
        const int mid = lo + ((hi - lo) / 2 + align / 2) / align * align;
        if (mid > lo && mid < hi && mid % align == 0) return mid;
    }
    return lo + (hi - lo) / 16 * 8;
}

} // namespace

ZoomPlan planZoomRegions(const SlicePlan& plan, const VoxelGrid& grid, const CrossSection& xs,
                         const ZoomPlanOptions& options, const std::optional<VoxelBox>& box) {
    if (options.fragmentBudget == 0) throw Error("fragment budget must be positive");
    if (options.maxRegionSize < 8 || options.maxRegionSize % 8) throw Error("region size must be a multiple of 8");
    ZoomPlan zp;
    // The voxels planned (the grid, or the box) and the whole bricks around them.
    const VoxelBox whole{glm::ivec3(0), grid.dims};
    const VoxelBox wanted = box ? intersect(*box, whole) : whole;
    if (wanted.empty()) throw Error("the box to plan holds no voxel of the grid");
    const VoxelBox root = roundOutToBricks(wanted);
    // A region's segments: those that reach its voxels in the box. Each
    // segment's box is found once, and the split reads those (24 bytes a
    // segment) and not the records (256), level after level.
    std::vector<SegmentVoxelBox> boxes(plan.segments.size());
    tbb::parallel_for(std::size_t(0), boxes.size(), [&](std::size_t s) {
        boxes[s] = segmentVoxelBox(plan, grid, static_cast<std::uint32_t>(s));
    });
    const auto reachingIn = [&](const std::vector<std::uint32_t>& from, glm::ivec3 min, glm::ivec3 max) {
        const VoxelBox part = intersect({min, max}, wanted);
        return filterSegments(from, [&](std::uint32_t s) { return boxes[s].reaches(part.min, part.max); });
    };
    std::vector<std::uint32_t> all(plan.segments.size());
    for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    std::vector<std::uint32_t> reaching = reachingIn(all, root.min, root.max);
    std::optional<TraceSpan> part(std::in_place, "the zoom plan's heat map");
    HeatMap heat(root, zp.heatCell, box.has_value());

    // Whether the run was given up (ZoomPlanOptions::stop): each segment's
    // slices and each region's split look, so a plan of many slices stops
    // within one segment's work a core.
    const auto stopped = [&] { return options.stop && options.stop->load(std::memory_order_relaxed); };
    addSliceHeat(heat, plan, grid, xs, options.supersample, reaching, stopped);
    if (stopped()) {
        zp.givenUp = true;
        return zp;
    }
    zp.heatCellsTouched = heat.touched();
    zp.estimatedFragments = heat.sum(root.min, root.max);
    part.emplace("the zoom plan's split");

    // Octree split; children in z, y, x order, and regions listed depth
    // first, so ids follow space. Children are split on every core, each
    // into its own list, and the lists are joined in child order: the same
    // plan whatever the scheduling.
    // Within half the budget, and small enough that the run has some
    // options.pipelineRegions regions (kPipelineRegions says why). A garment
    // expected to be small stays whole.
    if (!(options.pipelineRegions >= 1.0)) throw Error("a run is cut into at least one region");
    constexpr double kSmallRegion = 1 << 20;
    const double target = std::min(0.5 * double(options.fragmentBudget),
                                   std::max(kSmallRegion, zp.estimatedFragments / options.pipelineRegions));
    const std::function<std::vector<ZoomRegion>(glm::ivec3, glm::ivec3, std::vector<std::uint32_t>&&)> split =
        [&](glm::ivec3 min, glm::ivec3 max, std::vector<std::uint32_t>&& segments) -> std::vector<ZoomRegion> {
        if (segments.empty() || stopped()) return {};
        const glm::ivec3 size = max - min;
        const double estimate = heat.sum(min, max);
        const bool tooBig = glm::any(glm::greaterThan(size, glm::ivec3(options.maxRegionSize)));
        const bool tooHot = estimate > target && glm::any(glm::greaterThan(size, glm::ivec3(8)));
        if (!tooBig && !tooHot) {
            ZoomRegion r;
            r.min = min;
            r.max = max;
            r.segments = std::move(segments);
            r.estimatedFragments = estimate;
            std::vector<ZoomRegion> one;
            one.push_back(std::move(r));
            return one;
        }
        // Halve every axis more than a brick long, but for a thin one (at
        // most 128 voxels and a quarter of the longest): the yarns of a flat
        // garment cross its middle all along, and halving it drew every
        // slice near the middle twice (the raster took 2.5 times as long at
        // 4096, H100).
        const int longest = std::max({size.x, size.y, size.z});
        glm::ivec3 mid = max;
        for (int a = 0; a < 3; ++a) {
            const bool thin = size[a] <= 128 && 4 * size[a] <= longest;
            if (size[a] > 8 && !thin) mid[a] = splitPoint(min[a], max[a]);
        }
        std::vector<std::pair<glm::ivec3, glm::ivec3>> children;
        for (int z = 0; z < 2; ++z)
            for (int y = 0; y < 2; ++y)
                for (int x = 0; x < 2; ++x) {
                    const glm::ivec3 pick(x, y, z);
                    glm::ivec3 childMin, childMax;
                    bool exists = true;
                    for (int a = 0; a < 3; ++a) {
                        exists = exists && !(mid[a] == max[a] && pick[a] == 1); // axis not split
                        childMin[a] = pick[a] ? mid[a] : min[a];
                        childMax[a] = pick[a] ? max[a] : mid[a];
                    }
                    if (exists) children.emplace_back(childMin, childMax);
                }
        std::vector<std::vector<ZoomRegion>> parts(children.size());
        tbb::parallel_for(std::size_t(0), children.size(), [&](std::size_t i) {
            const auto& [childMin, childMax] = children[i];
            parts[i] = split(childMin, childMax, reachingIn(segments, childMin, childMax));
        });
        std::vector<ZoomRegion> out;
        for (auto& part : parts) std::move(part.begin(), part.end(), std::back_inserter(out));
        return out;
    };
    zp.regions = split(root.min, root.max, std::move(reaching));
    if (stopped()) {
        zp.regions.clear();
        zp.givenUp = true;
        return zp;
    }
    for (std::size_t i = 0; i < zp.regions.size(); ++i) zp.regions[i].id = i;
    return zp;
}

} // namespace yv

#include "cpu/cpu_region_backend.h"

#include "core/process_memory.h"

#include <tbb/parallel_pipeline.h>

#include <algorithm>

namespace yv {

CpuRegionBackend::CpuRegionBackend(const SlicePlan& plan, const CrossSection& xs, const VoxelGrid& grid,
                                   const VoxelizeSettings& settings,
                                   std::uint64_t sampleBudget)
    : plan_(plan), xs_(xs), grid_(grid), settings_(settings), quiet_(settings.quiet) {
    const std::uint64_t physical = physicalMemoryBytes();
    // Filled yarns give about two samples a voxel and fill the bricks they
    // touch about a quarter (14 KiB of accumulator words a brick): some 60
    // bytes a sample, counted three times over for the per-thread copies
    // merged at the end.
    // A budget asked for (--fragment-budget, perhaps sized for a GPU) is
    // capped at what a quarter of physical memory holds.
    const std::uint64_t cap = std::max<std::uint64_t>(physical / 4 / 200, std::uint64_t(1) << 20);
    memoryBudget_ = std::clamp<std::uint64_t>(physical / 16 / 200, std::uint64_t(1) << 20, std::uint64_t(1) << 27);
    budget_ = sampleBudget ? std::min(sampleBudget, cap) : memoryBudget_;
    // Regions have their own progress line; the slices inside them do not.
    settings_.quiet = true;
}

std::size_t CpuRegionBackend::regionsInFlight(const std::vector<ZoomRegion>& regions) const {
    double largest = 1.0;
    for (const ZoomRegion& region : regions) largest = std::max(largest, region.estimatedFragments);
    return std::clamp<std::size_t>(static_cast<std::size_t>(double(memoryBudget_) / largest), 1, kMaxRegionsInFlight);
}

void CpuRegionBackend::run(const std::vector<ZoomRegion>& regions, RegionSink& sink) {
    // A region's slices split over every core, but its start and end do not
    // (finding the slices that reach it, merging the threads' bricks, waking
    // TBB's workers): at thousands of small regions (--fragment-budget
    // 200000 at 2048) those parts set the pace on 16 cores, so small regions
    // are sampled several at a time. The sink still takes them one by one
    // in plan order, and is asked about each (resumed, or stop) in order.
    struct RegionWork {
        const ZoomRegion* region = nullptr;
        bool resumed = false;
        std::vector<BrickAccumulator> accumulators;
        CpuVoxelizeCounters counters;
    };
    Progress progress("voxelize", regions.size(), quiet_, "regions");
    std::size_t next = 0;
    tbb::parallel_pipeline(
        regionsInFlight(regions),
        tbb::make_filter<void, RegionWork>(tbb::filter_mode::serial_in_order,
                                           [&](tbb::flow_control& flow) {
                                               RegionWork work;
                                               if (next == regions.size() || sink.stopRequested()) {
                                                   flow.stop();
                                                   return work;
                                               }
                                               work.region = &regions[next++];
                                               work.resumed = sink.alreadyDone(*work.region);
                                               return work;
                                           }) &
            tbb::make_filter<RegionWork, RegionWork>(tbb::filter_mode::parallel,
                                                     [&](RegionWork work) {
                                                         if (work.resumed) return work;
                                                         const ZoomRegion& r = *work.region;
                                                         work.accumulators = accumulateBox(plan_, xs_, grid_, settings_, r.segments,
                                                                                           r.min, r.max, &work.counters);
                                                         return work;
                                                     }) &
            tbb::make_filter<RegionWork, void>(tbb::filter_mode::serial_in_order, [&](RegionWork work) {
                if (work.resumed) {
                    ++counters_.resumedRegions;
                } else {
                    counters_.sampling += work.counters;
                    ++counters_.regions;
                    sink.consumeAccumulators(*work.region, std::move(work.accumulators));
                }
                progress.advance(1);
            }));
    progress.finish();
}

JsonObject CpuRegionBackend::stats() const {
    JsonObject out;
    out.set("samples", counters_.sampling.samples)
        .set("threads", counters_.sampling.threads)
        .set("zoom_regions", counters_.regions + counters_.resumedRegions)
        .set("regions_computed", counters_.regions)
        .set("regions_resumed", counters_.resumedRegions)
        .set("fragment_budget", budget_);
    return out;
}

} // namespace yv

#include "cpu/cpu_region_backend.h"

#include "core/process_memory.h"

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
    budget_ = sampleBudget ? std::min(sampleBudget, cap)
                           : std::clamp<std::uint64_t>(physical / 16 / 200, std::uint64_t(1) << 20, std::uint64_t(1) << 27);
    // Regions have their own progress line; the slices inside them do not.
    settings_.quiet = true;
}

void CpuRegionBackend::run(const std::vector<ZoomRegion>& regions, RegionSink& sink) {
    forEachRegionToDo(regions, sink, quiet_, counters_.resumedRegions, [&](const ZoomRegion& region) {
        std::vector<BrickAccumulator> accumulators =
            accumulateBox(plan_, xs_, grid_, settings_, region.segments, region.min, region.max, &counters_.sampling);
        ++counters_.regions;
        sink.consumeAccumulators(region, std::move(accumulators));
    });
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

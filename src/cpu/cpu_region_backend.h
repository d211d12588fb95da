// The CPU reference as a region rasterizer: the zoom regions of the plan one
// after another, each from the segments that reach it, handed to a sink as
// they finish. Host memory then follows the largest region, not the volume,
// and the CPU backend has what the GL backend has: out of core, work
// directories and --resume.
#pragma once

#include "cpu/cpu_voxelizer.h"
#include "garment/cross_section.h"
#include "garment/slices.h"
#include "plan/grid.h"
#include "core/region_rasterizer.h"
#include "plan/zoom_plan.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace yv {

struct CpuRegionCounters {
    CpuVoxelizeCounters sampling;     ///< summed over regions
    std::uint64_t regions = 0;        ///< zoom regions computed
    std::uint64_t resumedRegions = 0; ///< zoom regions taken from a resumed work directory
};

class CpuRegionBackend : public RegionRasterizer {
  public:
    /// `sampleBudget`: samples one region may produce (0: from physical
    /// memory; at most what a quarter of physical memory holds).
    CpuRegionBackend(const SlicePlan& plan, const CrossSection& xs, const VoxelGrid& grid,
                     const VoxelizeSettings& settings, std::uint64_t sampleBudget = 0);
    /// Samples one region may produce (the zoom planner's budget): by default
    /// its accumulators stay within about a sixteenth of physical memory.
    /// (store_peak_queued_bytes in --stats shows what regions held.)
    std::uint64_t fragmentBudget() const override { return budget_; }
    /// Largest region edge in voxels (as the GL backend's, so both plan alike).
    int maxRegionSize() const override { return 1024; }
    /// The regions in plan order to the sink; small ones are sampled several
    /// at a time (see regionsInFlight).
    void run(const std::vector<ZoomRegion>& regions, RegionSink& sink) override;
    /// How many of `regions` may be sampled at the same time: as many as
    /// the default budget's memory holds of the largest, at most
    /// kMaxRegionsInFlight (1 where regions are as large as the budget; 8
    /// against 4: many small regions 1.0-1.05 times few rather than
    /// 1.06-1.37 at 1024 on the H200 machine's 16 cores).
    std::size_t regionsInFlight(const std::vector<ZoomRegion>& regions) const;
    static constexpr std::size_t kMaxRegionsInFlight = 8;
    /// samples, threads, zoom_regions, regions_computed, regions_resumed, fragment_budget.
    JsonObject stats() const override;
    std::uint64_t samples() const override { return counters_.sampling.samples; }
    const CpuRegionCounters& counters() const { return counters_; }

  private:
    const SlicePlan& plan_;
    const CrossSection& xs_;
    const VoxelGrid& grid_;
    VoxelizeSettings settings_;
    CpuRegionCounters counters_;
    std::uint64_t budget_ = 0;
    std::uint64_t memoryBudget_ = 0; ///< samples all regions in flight may hold together
    bool quiet_ = true; ///< no progress line
};

} // namespace yv

#include "pipeline/rasterizers.h"

#include "core/environment_count.h"
#include "core/trace.h"
#include "cpu/cpu_region_backend.h"
#include "gpu/gl_voxelizer.h"

#include <chrono>
#include <future>
#include <optional>
#include <thread>

namespace yv {
namespace {

/// The regions a run is cut into at least: kPipelineRegions, or
/// YV_PIPELINE_REGIONS (what the best count is depends on the GPU's cost of
/// a pass against the writer's of a region: measured with it, not rebuilt).
double pipelineRegions() {
    const std::optional<long> n = countFromEnvironment("YV_PIPELINE_REGIONS", 1, 65536, "regions");
    return n ? double(*n) : kPipelineRegions;
}

} // namespace

std::unique_ptr<RegionRasterizer> makeRasterizer(Backend backend, const SlicedGarment& sliced, const VoxelGrid& grid,
                                                 const VoxelizeSettings& base, const VoxelizeJob& job, GlStart&& gl) {
    if (backend == Backend::Cpu)
        return std::make_unique<CpuRegionBackend>(sliced.plan(), sliced.xs, grid, base, job.fragmentCapacity);
    GlVoxelizeSettings settings;
    settings.base = base;
    settings.fragmentCapacity = job.fragmentCapacity;
    settings.verbose = job.verbose && !job.quiet;
    settings.contextSeconds = gl.seconds;
    settings.slicePrimitive = job.sampleItems == SampleItemsRequest::Compute ? SlicePrimitive::Compute
                              : job.sampleItems == SampleItemsRequest::Raster ? SlicePrimitive::Raster
                                                                             : SlicePrimitive::Auto;
    const TraceSpan span("set up the GL backend");
    if (gl.context) return std::make_unique<GlBackend>(sliced.plan(), sliced.xs, grid, settings, std::move(gl.context));
    return std::make_unique<GlBackend>(sliced.plan(), sliced.xs, grid, settings, *gl.kept);
}

ZoomPlan planZoomWhilePreparing(RegionRasterizer& rasterizer, const SlicedGarment& sliced, const VoxelGrid& grid,
                                int supersample, const std::optional<VoxelBox>& box, Cluster* group,
                                const std::atomic<bool>* stop, double& seconds) {
    // The ranks' budgets differ (each sees what the others left free).
    const std::uint64_t budget = group ? group->broadcast(rasterizer.fragmentBudget()) : rasterizer.fragmentBudget();
    // Every rank plans alike: rank 0's count of regions, as its budget.
    const double regions = group ? double(group->broadcast(std::uint64_t(pipelineRegions()))) : pipelineRegions();
    const ZoomPlanOptions options{budget, rasterizer.maxRegionSize(), supersample, stop, regions};
    std::future<ZoomPlan> pending = std::async(std::launch::async, [&] {
        const auto start = std::chrono::steady_clock::now();
        ZoomPlan planned = planZoomRegions(sliced.plan(), grid, sliced.xs, options, box);
        traceSpanSince("plan the zoom regions", start);
        seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return planned;
    });
    rasterizer.prepare();
    return pending.get();
}

std::jthread freeInBackground(std::unique_ptr<RegionRasterizer> rasterizer) {
    rasterizer->releaseThread();
    return std::jthread([r = std::move(rasterizer)]() mutable {
        const TraceSpan span("free the GPU's buffers and context");
        r.reset();
    });
}

} // namespace yv

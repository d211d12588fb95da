#include "pipeline/rasterizers.h"

#include "core/trace.h"
#include "cpu/cpu_region_backend.h"
#include "gpu/gl_voxelizer.h"

#include <chrono>
#include <future>
#include <thread>

namespace yv {
namespace {

/// What GlBackend refers to for its lifetime: kept beside it.
struct GlBackendState {
    GlVoxelizeSettings settings;
    GlVoxelizeCounters counters;
};

class GlRasterizer : private GlBackendState, public GlBackend {
  public:
    GlRasterizer(GlBackendState state, const SlicedGarment& s, const VoxelGrid& grid, std::unique_ptr<GlContext> context)
        : GlBackendState(std::move(state)), GlBackend(s.plan, s.xs, grid, settings, counters, std::move(context)) {}
};

} // namespace

std::unique_ptr<RegionRasterizer> makeRasterizer(Backend backend, const SlicedGarment& sliced, const VoxelGrid& grid,
                                                 const VoxelizeSettings& settings, const VoxelizeJob& job, GlStart&& gl) {
    if (backend == Backend::Cpu)
        return std::make_unique<CpuRegionBackend>(sliced.plan, sliced.xs, grid, settings, job.fragmentCapacity);
    GlBackendState state;
    state.settings.base = settings;
    state.settings.device = job.device;
    state.settings.spreadIndex = cluster() ? cluster()->localRank() : 0; // each rank its own GPU, alone or not
    state.settings.fragmentCapacity = job.fragmentCapacity;
    state.settings.verbose = job.verbose && !job.quiet;
    state.counters.contextSeconds = gl.seconds;
    const TraceSpan span("set up the GL backend");
    return std::make_unique<GlRasterizer>(std::move(state), sliced, grid, std::move(gl.context));
}

ZoomPlan planZoomWhilePreparing(RegionRasterizer& rasterizer, const SlicedGarment& sliced, const VoxelGrid& grid,
                                int supersample, Cluster* group, double& seconds) {
    // The ranks' budgets differ (each sees what the others left free).
    const std::uint64_t budget = group ? group->broadcast(rasterizer.fragmentBudget()) : rasterizer.fragmentBudget();
    std::future<ZoomPlan> pending = std::async(std::launch::async, [&] {
        const auto start = std::chrono::steady_clock::now();
        ZoomPlan planned = planZoomRegions(sliced.plan, grid, sliced.xs, {budget, rasterizer.maxRegionSize(), supersample});
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

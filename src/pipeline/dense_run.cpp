#include "pipeline/dense_run.h"

#include "gpu/dense_voxelizer.h"

namespace yv {

DenseRun runDense(const SlicedGarment& sliced, const VoxelGrid& grid, const VoxelizeSettings& settings,
                  const VoxelizeJob& job, GlStart&& gl, VolumeMetadata& meta, const VdbWriteOptions& writeOptions,
                  StageTimer& timer, const RefuseEmpty& refuseEmpty) {
    GlVoxelizeSettings glSettings;
    glSettings.base = settings;
    glSettings.device = job.device;
    DenseVoxelizeCounters counters;
    gl.context.reset(); // voxelizeDense makes its own
    const BrickVolume volume = voxelizeDense(sliced.plan, sliced.xs, grid, glSettings, &counters);
    DenseRun run;
    run.voxelizeSeconds = timer.lap("voxelize");
    meta.backend = "gl-dense";
    run.totals.activeVoxels = volume.activeVoxelCount();
    refuseEmpty(run.totals.activeVoxels);
    writeVdb(job.output, volume, meta, writeOptions);
    timer.lap("write");
    run.totals.bricks = volume.bricks.size();
    run.totals.writer.tally = volume.tally;
    run.backendStats.set("renderer", counters.renderer)
        .set("platform", counters.platform)
        .set("method", "dense")
        .set("gpu_peak_bytes", counters.textureBytes)
        .set("slices_drawn", counters.instances)
        .set("gpu_clear_seconds", counters.clearSeconds)
        .set("gpu_raster_seconds", counters.rasterSeconds)
        .set("readback_seconds", counters.readbackSeconds);
    return run;
}

} // namespace yv

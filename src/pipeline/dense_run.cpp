#include "pipeline/dense_run.h"

#include "gpu/dense_voxelizer.h"

namespace yv {

DenseRun runDense(const SlicedGarment& sliced, const VoxelGrid& grid, const VoxelizeSettings& settings,
                  const VoxelizeJob& job, GlStart&& gl, VolumeMetadata& meta, const VdbWriteOptions& writeOptions,
                  StageTimer& timer, const RefuseEmpty& refuseEmpty) {
    GlVoxelizeSettings glSettings;
    glSettings.base = settings;
    DenseVoxelizeCounters counters;
    const BrickVolume volume = voxelizeDense(sliced.plan(), sliced.xs, grid, glSettings, *gl.current(), &counters);
    DenseRun run;
    run.voxelizeSeconds = timer.lap("voxelize");
    meta.backend = "gl-dense";
    run.totals.activeVoxels = volume.activeVoxelCount();
    refuseEmpty(run.totals.activeVoxels);
    writeVdb(job.output, volume, meta, writeOptions);
    timer.lap("write");
    run.totals.bricks = volume.bricks.size();
    run.totals.writer.tally = volume.tally;
    run.backendStats = toJson(counters);
    return run;
}

} // namespace yv

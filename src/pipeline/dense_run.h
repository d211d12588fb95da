// The paper's method, kept as a benchmark baseline: the whole grid in one set
// of dense 3D textures on GL, read back as bricks and written as a .vdb.
#pragma once

#include "core/stats.h"
#include "pipeline/backend_choice.h"
#include "pipeline/region_destination.h"
#include "pipeline/sliced_garment.h"
#include "pipeline/stage_timer.h"

namespace yv {

struct DenseRun {
    RunTotals totals;
    double voxelizeSeconds = 0.0;
    JsonObject backendStats;
};

/// Voxelizes the sliced garment with the dense method on `gl`'s context and
/// writes the .vdb; laps "voxelize" and "write" on `timer`.
DenseRun runDense(const SlicedGarment& sliced, const VoxelGrid& grid, const VoxelizeSettings& settings,
                  const VoxelizeJob& job, GlStart&& gl, VolumeMetadata& meta, const VdbWriteOptions& writeOptions,
                  StageTimer& timer, const RefuseEmpty& refuseEmpty);

} // namespace yv

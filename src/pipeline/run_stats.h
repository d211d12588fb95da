// The --stats file of a run: what it was asked, what it made, and where the
// time went (one JSON object, its keys documented in README's "--stats").
#pragma once

#include "core/stats.h"
#include "core/voxel_grid.h"
#include "pipeline/backend_choice.h"
#include "pipeline/region_destination.h"
#include "pipeline/sliced_garment.h"
#include "pipeline/stage_timer.h"
#include "vdb/vdb_writer.h"

#include <optional>

namespace yv {

/// Everything a finished run's statistics are made of.
struct RunRecord {
    const VoxelizeJob& job;
    Backend backend;
    const SlicedGarment& sliced;
    const VoxelGrid& grid;
    const RunTotals& totals;
    std::uint64_t samples = 0; ///< samples that landed on fibre (0 for the dense method)
    double voxelizeSeconds = 0.0;
    const VdbWriteTimings& writeTimings;
    const StageTimer& timer;
    JsonObject backendStats; ///< the rasterizer's counters and the destination's
    std::optional<JsonObject> box; ///< --bbox: the box's record (voxelize_box.h), after grid_dims
};

/// The run's --stats object, keys in their documented order.
JsonObject runStats(const RunRecord& run);

/// The destination's part of "backend_stats", after the rasterizer's own
/// counters: the run's region totals (replacing the rasterizer's), the
/// writer's times, where the regions went and how many ranks shared them.
void addDestinationStats(JsonObject& backendStats, const RunTotals& totals, std::size_t plannedRegions,
                         double zoomPlanSeconds, const char* regionsTo, int ranks);

} // namespace yv

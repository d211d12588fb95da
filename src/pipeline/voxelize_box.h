// A --bbox run's box: placed on the grid once the grid is known, the part of
// the garment that reaches it, and what the run says and records of it.
#pragma once

#include "core/stats.h"
#include "core/voxel_grid.h"
#include "pipeline/sliced_garment.h"
#include "pipeline/voxelize_job.h"
#include "plan/box_request.h"

#include <cstdint>
#include <optional>

namespace yv {

/// The box on the grid, and the segments whose slices can reach it (by their
/// whole footprint, not their centres: zoom_plan.h, segmentVoxelBounds).
struct RunBox {
    BoxOnGrid placed;
    std::uint64_t segments = 0, slices = 0; ///< segments reaching the box, and their slices
    double yarnLength = 0.0;                ///< their arc length, for the disk estimate
};

/// None without --bbox. Throws yv::Error, one line naming the option and its
/// value, when the box misses the grid or no yarn reaches it; tells (under
/// --verbose) where the box lies, and that it was clipped to the grid.
std::optional<RunBox> placeRunBox(const VoxelizeJob& job, const SlicedGarment& sliced, const VoxelGrid& grid,
                                  const Tell& tell);

/// --stats' "bbox": the option as asked, the voxels run (max exclusive) and
/// their world box, whether they were clipped, what reaches them.
JsonObject boxStats(const VoxelizeJob& job, const RunBox& box, const VoxelGrid& grid);

} // namespace yv

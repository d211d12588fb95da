// The first stage of a run: the garment read, checked and sliced.
#pragma once

#include "garment/cross_section.h"
#include "garment/garment.h"
#include "garment/slices.h"
#include "pipeline/stage_timer.h"
#include "pipeline/voxelize_job.h"
#include "pipeline/yarn_radius.h"
#include "plan/resource_estimate.h"

#include <optional>

namespace yv {

/// What reading and slicing the garment gives the rest of the run.
struct SlicedGarment {
    Garment garment;
    CrossSection xs;
    YarnRadiusChoice radius;
    SliceOptions sliceOptions;
    bool explicitSpacing = false; ///< --slices-per-segment or --slice-spacing asked for
    SlicePlan plan;
};

/// Reads the garment and tidies its curves, makes the cross-section, chooses
/// the yarn radius, refuses a run that would leave no voxels or does not fit
/// on disk (`throughWorkDir`: the regions go through a work directory too),
/// and places the slices (one a supersampled voxel along the yarn unless the
/// job says otherwise). Laps "read" and "slices" on `timer`; warnings go to
/// `tell`. Throws yv::Error naming the input.
SlicedGarment sliceGarment(const VoxelizeJob& job, bool throughWorkDir, const Tell& tell, StageTimer& timer);

/// Refuses, once the slices lie on `grid`, a run whose expected output (the
/// .vdb as `shape` stores it, its scratch file, the work dir's regions) does
/// not fit the free disk: the bound sliceGarment checks before slicing
/// catches only runs far too large. `boxYarnLength`: a --bbox run's, the
/// arc length of the segments that reach its box (the whole garment's
/// otherwise). Throws yv::Error naming the input, the bytes expected and
/// free, and what to change.
void checkOutputFits(const VoxelizeJob& job, bool throughWorkDir, const SlicedGarment& sliced, const VoxelGrid& grid,
                     const VdbShape& shape, std::optional<double> boxYarnLength = std::nullopt);

} // namespace yv

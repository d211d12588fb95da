// The second stage of a run: the chosen backend made into a region
// rasterizer, and the zoom regions planned while it gets ready.
#pragma once

#include "core/region_rasterizer.h"
#include "core/voxel_grid.h"
#include "core/voxelize_settings.h"
#include "pipeline/backend_choice.h"
#include "pipeline/cluster.h"
#include "pipeline/sliced_garment.h"
#include "plan/zoom_plan.h"

#include <atomic>
#include <memory>
#include <thread>

namespace yv {

/// The rasterizer of `backend` (Cpu or Gl) over the sliced garment; the GL
/// backend runs on `gl`'s context. Both keep references to `sliced` and `grid`.
std::unique_ptr<RegionRasterizer> makeRasterizer(Backend backend, const SlicedGarment& sliced, const VoxelGrid& grid,
                                                 const VoxelizeSettings& settings, const VoxelizeJob& job, GlStart&& gl);

/// The zoom regions, planned on the host's cores while `rasterizer` does the
/// work that needs no plan (the GL backend's upload and programs, on this
/// thread). The ranks of an MPI run (`group`) all plan with rank 0's budget,
/// so they plan the same regions. `box`: a --bbox run's box, the only voxels
/// planned. `stop`: where set, the planning stops soon after it is
/// (ZoomPlanOptions::stop). `seconds`: how long the planning took.
ZoomPlan planZoomWhilePreparing(RegionRasterizer& rasterizer, const SlicedGarment& sliced, const VoxelGrid& grid,
                                int supersample, const std::optional<VoxelBox>& box, Cluster* group,
                                const std::atomic<bool>* stop, double& seconds);

/// Destroys the rasterizer on a thread of its own (the GL backend's buffers
/// and context take tens of ms to free) while the caller goes on to write the
/// output; the thread is joined where the returned handle goes.
std::jthread freeInBackground(std::unique_ptr<RegionRasterizer> rasterizer);

} // namespace yv

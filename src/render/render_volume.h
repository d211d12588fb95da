// One picture of a work directory, a .vdb or a garment, on the context the
// command lends (`yarnvox inspect --render`, the HTML report's renders).
// Picks the level of detail the GPU budget allows, streams only that level's
// bricks into a brick atlas, frames the volume (or one zoom region) and
// draws it with the renderer of the requested mode; a cut is read at full
// resolution on the host instead.
#pragma once

#include "garment/slices.h"
#include "inspect/render_request.h"
#include "inspect/volume_source.h"
#include "plan/grid.h"
#include "render/brick_atlas.h"
#include "render/render_context.h"
#include "render/renderer.h"

#include <memory>

namespace yv {

/// What a renderer draws, as its mode needs it: a volume's level in a brick
/// atlas (raycast, mip, orientation, isosurface, texture-slicing,
/// half-angle, splatting), the run's slices (slices), or a garment's slices
/// placed on a grid (volumetric-triangles).
struct RenderInput {
    const BrickAtlas* atlas = nullptr;
    const SliceInstances* slices = nullptr;
    const SlicePlan* plan = nullptr;
    const VoxelGrid* grid = nullptr;
    double yarnDensity = 1.0; ///< volumetric-triangles: the cross-section's mean density inside the yarn's disk
    bool onGpu = false;       ///< slices: the context is a GPU's (GlInfo::hardware(); SliceSettings::onGpu)
};

/// The renderer of `request.kind` with its settings from `request`, for
/// `input` (the context must be current). Throws yv::Error for a cut (drawn
/// on the host, renderCut) or an input the mode does not draw.
std::unique_ptr<Renderer> makeRenderer(const RenderRequest& request, const RenderInput& input);

/// Renders `source` as `request` asks, on `context`'s GL context (made here
/// where none was yet; a cut needs none). Throws yv::Error (no GL context,
/// an empty volume, a region the source lacks, a budget that holds no level).
RenderReport renderVolume(RenderContext& context, const VolumeSource& source, const RenderRequest& request);

/// Draws the slices of `plan`, placed on `grid`, as volumetric triangles,
/// with the camera framing `box` as the other renders frame a volume (see
/// VolumetricTriangleRenderer). Throws yv::Error (no GL context, no slices).
RenderReport renderVolumetricTriangles(RenderContext& context, const SlicePlan& plan, const VoxelGrid& grid,
                                       const VoxelBox& box, const RenderRequest& request, double yarnDensity = 1.0);

} // namespace yv

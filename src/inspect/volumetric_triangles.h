// `--render volumetric-triangles`: a garment previewed as a soft volume
// without voxelizing it. Every slice's square (two triangles) is drawn as a
// Gaussian-blurred volumetric triangle, after the appendix of
// ../shared/reference/volumetric-triangle-shader-appendix.txt: a geometry
// shader bounds each triangle on screen, a fragment shader integrates its
// absorbance along the view ray, and the absorbances add up per pixel.
#pragma once

#include "garment/slices.h"
#include "inspect/inspect_render.h"
#include "plan/grid.h"

namespace yv {

/// The box of brick-aligned voxels the slices of `plan` reach on `grid`,
/// clipped to the grid: what a volume voxelized from them frames.
VoxelBox sliceBox(const SlicePlan& plan, const VoxelGrid& grid);

/// Draws the slices of `plan`, placed on `grid` (coordinates in its voxels),
/// with the camera framing `box` as the other renders frame a volume. Each
/// slice's slab holds fibre of density `yarnDensity` inside the yarn's disk;
/// the picture's colour and opacity per voxel of yarn are the transfer
/// function's at that density, as the ray cast of a volume of it would
/// show. Throws yv::Error (no GL context, no slices).
RenderReport renderVolumetricTriangles(const SlicePlan& plan, const VoxelGrid& grid, const VoxelBox& box,
                                       const RenderRequest& request, double yarnDensity = 1.0);

} // namespace yv

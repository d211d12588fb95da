// Choosing the voxel grid for a garment: its box, padding and voxel size.
#pragma once

#include "core/voxel_grid.h"
#include "garment/slices.h"

#include <cmath>
#include <cstdint>

namespace yv {


/// How far (voxels) a sample's footprint cells reach beyond its slice's
/// square and slab: a pixel beyond the square's projection, and its cells'
/// columns meet the tilted slice up to a voxel deeper.
constexpr double kSampleReachVoxels = 2.0;

/// Grid around every slice of a plan: the garment box is the curves' bounds
/// grown by the slice half-diagonal radius * sqrt(2); it is padded by one
/// voxel and by how far slabs reach along their projection axis. Exactly one
/// of `resolution` (voxels along the longest axis of the garment box) and
/// `voxelSize` must be positive.
VoxelGrid makeGrid(const SlicePlan& plan, int resolution, double voxelSize);

/// The voxel size makeGrid will choose for any plan of this garment with this
/// radius: known before the slices are planned, so that the slice spacing can
/// follow it (defaultSliceSpacing).
double voxelSizeFor(const Garment& garment, double radius, int resolution, double voxelSize);
/// The same from the curves' bounds (curveBounds), where the caller has them.
double voxelSizeForCurves(const glm::dvec3& curveMin, const glm::dvec3& curveMax, double radius, int resolution,
                          double voxelSize);

} // namespace yv

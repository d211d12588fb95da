// The voxel grid: where voxel (i, j, k) lies in the world.
#pragma once

#include "garment/slices.h"

#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>

namespace yv {

/// Voxel (i, j, k) covers origin + [i, i+1) * voxelSize (and likewise in j, k);
/// its centre is origin + (i + 0.5) * voxelSize. Dimensions are multiples of
/// 8, so the grid is a whole number of 8^3 bricks.
struct VoxelGrid {
    glm::dvec3 origin{0.0};
    double voxelSize = 1.0;
    glm::ivec3 dims{0};

    std::uint64_t voxelCount() const { return std::uint64_t(dims.x) * dims.y * dims.z; }
    glm::ivec3 brickDims() const { return dims / 8; }
};

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

} // namespace yv

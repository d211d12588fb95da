// What planning needs of a segment's slices, found from every one of them:
// its length (the sum of the slices' thicknesses), the bounds of their
// centres, how far their samples reach, and its largest slice thickness; and
// where each lies for the zoom plan's heat. At the paper's 50 slices a
// segment that is tens of millions of slices a garment, so they are measured
// two (SSE2) or four (AVX) at a time, each lane the same operations as one
// slice at a time (sliceOnCurve, glm): the same bits.
#pragma once

#include "garment/slices.h"

#include <glm/vec3.hpp>

#include <cstdint>

namespace yv {

/// Which lanes measureSlices may use: Auto picks AVX where the CPU has it
/// (cpuHasAvx), else SSE2; Avx only where it has. Tests force each path,
/// and Scalar (one slice at a time, through sliceOnCurve) is what every path
/// must equal.
enum class SliceLanes { Auto, Scalar, Sse2, Avx };

struct SegmentMeasures {
    double length = 0.0;  ///< the sum of the slices' thicknesses, in slice order
    double spacing = 0.0; ///< the largest slice thickness
    double reach = 0.0;   ///< the farthest a sample of a slice lies from its centre
    glm::dvec3 centerMin{0.0}, centerMax{0.0};
    bool flat = false; ///< a slice has no tangent (repeated control points)
};

/// Measures the `segment.sliceCount` slices of `segment` (its points set);
/// `halfDiagonal`: half the slice square's diagonal, the least reach.
/// Reach: the half-diagonal in the slice's plane plus half the slab's depth
/// along its projection axis, which a bend thickens on its outer side by up
/// to kappa r sqrt(2).
SegmentMeasures measureSlices(const SegmentRecord& segment, double halfDiagonal, SliceLanes lanes = SliceLanes::Auto);

/// What drawing a slice takes of it (sliceOnCurve's centre, tangent and
/// thickness; no frame).
struct SliceAxis {
    glm::dvec3 centre, tangent;
    double thickness;
};

/// Slices first .. first + count - 1 of `segment` (within its sliceCount),
/// each the values sliceOnCurve gives, into out[0 .. count - 1]. The curve
/// must move at every slice (planSlices refuses a segment where it does not).
void sliceAxes(const SegmentRecord& segment, std::uint32_t first, std::uint32_t count, SliceAxis* out,
               SliceLanes lanes = SliceLanes::Auto);

/// Where a slice lies, as the zoom plan's heat estimates it (at t = (k +
/// 0.5) / K, divided): the voxel holding that point of the curve, and the
/// largest component of its unit tangent there.
struct SliceInGrid {
    glm::ivec3 voxel;
    double dominant;
};

/// Slices first .. first + count - 1 of `segment` (within its sliceCount)
/// on the grid of voxels `voxelSize` wide from `origin`, into out[0 .. count
/// - 1]. Scalar: glm's evalCatmullRom, floor, normalize and abs, one slice
/// at a time; every path gives its bits.
void slicesInGrid(const SegmentRecord& segment, std::uint32_t first, std::uint32_t count, const glm::dvec3& origin,
                  double voxelSize, SliceInGrid* out, SliceLanes lanes = SliceLanes::Auto);

} // namespace yv

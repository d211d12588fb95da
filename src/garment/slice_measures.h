// What planning needs of a segment's slices, found from every one of them:
// its length (the sum of the slices' thicknesses), the bounds of their
// centres, how far their samples reach, and its largest slice thickness; and
// where each lies for the zoom plan's heat. At the paper's 50 slices a
// segment that is tens of millions of slices a garment, so they are measured
// two (SSE2) or four (AVX) at a time, each lane the same operations as one
// slice at a time (sliceOnCurve, glm): the same bits.
#pragma once

#include "garment/slices.h"

#include <glm/common.hpp>
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
    /// The sum, in slice order, of the largest component of each slice's
    /// unit tangent (the slab's depth in voxels per voxel of thickness):
    /// the zoom plan's heat takes its mean.
    double dominantSum = 0.0;
    glm::dvec3 centerMin{0.0}, centerMax{0.0};
    bool flat = false; ///< a slice has no tangent (repeated control points)
};

/// Measures the `segment.sliceCount` slices of `segment` (its points set);
/// `halfDiagonal`: half the slice square's diagonal, the least reach.
/// Reach: the half-diagonal in the slice's plane plus half the slab's depth
/// along its projection axis, which a bend thickens on its outer side by up
/// to kappa r sqrt(2).
SegmentMeasures measureSlices(const SegmentRecord& segment, double halfDiagonal, SliceLanes lanes = SliceLanes::Auto);

/// The largest of the curve's speeds |dC/dt| at t = 0, 1/16, ..., 1 (17
/// points) on a segment with control points `points`: every path gives the
/// bits of glm::length(evalCatmullRomDerivative(points, j / 16.0)), one at a time.
double fastestCurveSpeed(const SegmentPoints& points, SliceLanes lanes = SliceLanes::Auto);

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

/// The voxel holding point `p` on a grid of voxels 1 / invVoxelSize wide
/// from `origin`: floor((p - origin) * invVoxelSize), monotonic in `p`. What
/// sliceVoxels gives each slice's centre, so the voxels of a segment's
/// centre bounds bound its slices'.
inline glm::ivec3 voxelHolding(const glm::dvec3& p, const glm::dvec3& origin, double invVoxelSize) {
    return glm::ivec3(glm::floor((p - origin) * invVoxelSize));
}

/// The voxel holding each of slices first .. first + count - 1 of `segment`
/// (within its sliceCount), voxelHolding the centre sliceOnCurve gives, into
/// out[0 .. count - 1]: where the zoom plan's heat puts each slice. Every
/// path gives the scalar one's bits (glm's evalCatmullRom and voxelHolding,
/// one slice at a time), so the voxels of a segment's centerMin and
/// centerMax bound its slices' voxels.
void sliceVoxels(const SegmentRecord& segment, std::uint32_t first, std::uint32_t count, const glm::dvec3& origin,
                 double invVoxelSize, glm::ivec3* out, SliceLanes lanes = SliceLanes::Auto);

} // namespace yv

// Slices: oriented cross-sections placed along each yarn (paper, section 3.3).
//
// Slices are never stored as matrices. A SlicePlan keeps, per curve segment,
// what any backend needs to place that segment's slices itself: the four
// control points, the slice count, the twist phase and rate, and the
// parallel-transported frame at the segment's first knot. The CPU backend
// evaluates slices from it; the GL vertex shader does the same per instance.
#pragma once

#include "core/default_init_allocator.h"
#include "garment/catmull_rom.h"
#include "garment/garment.h"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <type_traits>
#include <vector>

namespace yv {

struct SliceOptions {
    /// Slices per curve segment (the paper uses 25 and 50). Ignored when spacing > 0.
    int slicesPerSegment = 25;
    /// Target distance between slices along the yarn (world units); 0: use
    /// slicesPerSegment. The command line's default is defaultSliceSpacing().
    double spacing = 0.0;
    /// Yarn twist: rotation of the cross-section about the yarn, radians per world unit.
    double twist = 0.0;
    /// Yarn radius (world units): slices are squares of side 2 radius.
    double radius = 0.1;
    bool operator==(const SliceOptions&) const = default;
};

/// One curve segment of one yarn, with what it takes to place its slices.
/// Trivial on purpose: planSlices sets every field (value-initializing each
/// record on the thread that fills it), see DefaultInitAllocator.
struct SegmentRecord {
    SegmentPoints points;      ///< P[i-1], P[i], P[i+1], P[i+2]
    glm::dvec3 knotTangent;    ///< unit tangent at t = 0 (at a cusp, the one the curve leaves by)
    glm::dvec3 knotUp;         ///< frame "up" at t = 0, perpendicular to knotTangent
    double arcStart;           ///< arc length of the yarn before this segment
    double length;             ///< arc length of this segment (sum of its slices' thicknesses)
    double phaseStart;         ///< twist phase at t = 0, radians in [0, 2 pi)
    double twistRate;          ///< twist, radians per world unit (closed yarns: adjusted so the loop closes)
    double reach;              ///< farthest any sample of a slice of this segment lies from its slice centre
    double meanDominant;       ///< mean over its slices of the largest component of the unit tangent (the zoom plan's heat)
    std::uint64_t firstSlice;
    std::uint32_t sliceCount;
    std::uint32_t yarn;
    glm::dvec3 centerMin, centerMax; ///< bounds of this segment's slice centres
};
static_assert(std::is_trivially_default_constructible_v<SegmentRecord>);

struct SlicePlan {
    SliceOptions options;
    std::vector<SegmentRecord, DefaultInitAllocator<SegmentRecord>> segments;
    std::uint64_t sliceCount = 0;
    glm::dvec3 centerMin{0.0}, centerMax{0.0}; ///< bounds of all slice centres
    glm::dvec3 curveMin{0.0}, curveMax{0.0};   ///< exact bounds of the curves (see curveBounds)
    double maxReach = 0.0;                     ///< largest SegmentRecord::reach
    double maxSpacing = 0.0;                   ///< largest slice thickness (distance between slices)
    double yarnLength = 0.0;                   ///< the segments' lengths summed in order
    std::uint32_t fewestSlices = 0, mostSlices = 0; ///< the least and most slices of a segment (0 without segments)

    /// The slices of every segment where all have as many, else 0.
    std::uint32_t uniformSlices() const { return fewestSlices == mostSlices ? mostSlices : 0; }
};

/// A placed slice: a square of side 2 radius centred at `center`, spanned by
/// `right` and `up`, with normal `tangent`; `thickness` is the length of yarn
/// it stands for; the cross-section is turned by `twistStep` radians at the
/// next slice. `curvature` is the curve's curvature vector (kappa times the
/// unit normal, 1 / world units): the slab is thinner on its inner side.
struct Slice {
    glm::dvec3 center, tangent, right, up;
    double thickness = 0.0;
    double twistStep = 0.0;
    std::uint32_t yarn = 0;
    glm::dvec3 curvature{0.0};
};

/// The command line's slice spacing: one slice per (supersampled) voxel along
/// the yarn, whatever the spacing of the garment's control points.
inline double defaultSliceSpacing(double voxelSize, int supersample) { return voxelSize / supersample; }

/// Exact bounds of every yarn's curve (the slice centres lie on it).
void curveBounds(const Garment& garment, glm::dvec3& lo, glm::dvec3& hi);

/// Relative thickness of the slab at slice-local (x, y): the tube's Jacobian
/// 1 - kappa rho cos(theta), i.e. 1 - curvature . (x right + y up), at least 0
/// (a bend tighter than the offset folds the tube onto itself).
inline double slabScale(const Slice& slice, double x, double y) {
    const double j = 1.0 - glm::dot(slice.curvature, x * slice.right + y * slice.up);
    return j > 0.0 ? j : 0.0;
}

/// Plans the slices of a garment: slice counts, arc lengths and knot frames,
/// transported from knot to knot without flips. On a closed yarn the frame's
/// holonomy (the angle it comes back turned by) and the twist are spread
/// evenly over the loop, so the cross-section turns by the same angle per
/// unit length across the closing point as anywhere else. At a knot where
/// the curve turns straight back (a cusp, no tangent) the frame is carried
/// over to the tangent the curve leaves by (knotDirection): the curve itself
/// is unchanged. Throws yv::Error on a yarn with fewer than 2 points or with
/// repeated points that leave no tangent.
SlicePlan planSlices(const Garment& garment, const SliceOptions& options);
/// The same, given the curves' bounds as curveBounds finds them (a caller
/// that has found them already: a pass over every segment less).
SlicePlan planSlices(const Garment& garment, const SliceOptions& options, const glm::dvec3& curveMin,
                     const glm::dvec3& curveMax);

/// Below this speed |dC/dt| the curve has no tangent (SliceOnCurve::hasTangent).
constexpr double kLeastCurveSpeed = 1e-12;

/// What the slice bounds need of slice `k`: where it sits, how thick it is
/// and how the curve bends there, without its frame.
struct SliceOnCurve {
    glm::dvec3 center, derivative, tangent{0.0}, curvature{0.0};
    double thickness = 0.0;
    bool hasTangent = false; ///< the curve moves there (else tangent and curvature are zero)
};
SliceOnCurve sliceOnCurve(const SegmentRecord& segment, std::uint32_t k);

/// Slice `k` (0 <= k < sliceCount) of a segment. Slice k sits at the middle of
/// parameter interval [k/K, (k+1)/K]; its thickness is that interval's arc length.
Slice placeSlice(const SegmentRecord& segment, std::uint32_t k);

/// Rotates v by the smallest rotation that takes unit vector `from` to unit vector `to`.
glm::dvec3 rotateMinimal(const glm::dvec3& v, const glm::dvec3& from, const glm::dvec3& to);

/// Fiber direction (unit, world space) at slice-local (x, y) from the twist
/// between this slice and the next (the paper's eq. 1), sign along the tangent.
glm::dvec3 fiberDirection(const Slice& slice, double x, double y);

/// The cosine and sine of a slice's twist step, found once for all of its samples.
struct FiberTwist {
    double cos = 1.0, sin = 0.0;
};
FiberTwist fiberTwist(const Slice& slice);
/// fiberDirection with the slice's twist found beforehand: the same bits.
glm::dvec3 fiberDirection(const Slice& slice, const FiberTwist& twist, double x, double y);

} // namespace yv

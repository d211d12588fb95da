// Slices: oriented cross-sections placed along each yarn (paper, section 3.3).
//
// Slices are never stored as matrices. A SlicePlan keeps, per curve segment,
// what any backend needs to place that segment's slices itself: the four
// control points, the slice count, the arc length so far (for the twist) and
// the parallel-transported frame at the segment's first knot. The CPU backend
// evaluates slices from it; the GL vertex shader does the same per instance.
#pragma once

#include "garment/catmull_rom.h"
#include "garment/garment.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace yv {

struct SliceOptions {
    /// Slices per curve segment (the paper uses 25 and 50). Ignored when spacing > 0.
    int slicesPerSegment = 25;
    /// Target distance between slices along the yarn (world units); 0: use slicesPerSegment.
    double spacing = 0.0;
    /// Yarn twist: rotation of the cross-section about the yarn, radians per world unit.
    double twist = 0.0;
    /// Yarn radius (world units): slices are squares of side 2 radius.
    double radius = 0.1;
};

/// One curve segment of one yarn, with what it takes to place its slices.
struct SegmentRecord {
    SegmentPoints points;     ///< P[i-1], P[i], P[i+1], P[i+2]
    glm::dvec3 knotTangent;   ///< unit tangent at t = 0
    glm::dvec3 knotUp;        ///< frame "up" at t = 0, perpendicular to knotTangent
    double arcStart = 0.0;    ///< arc length of the yarn before this segment (sum of slice chords)
    double length = 0.0;      ///< sum of this segment's slice chords
    std::uint64_t firstSlice = 0;
    std::uint32_t sliceCount = 0;
    std::uint32_t yarn = 0;
    glm::dvec3 centerMin{0.0}, centerMax{0.0}; ///< bounds of this segment's slice centres
};

struct SlicePlan {
    SliceOptions options;
    std::vector<SegmentRecord> segments;
    std::uint64_t sliceCount = 0;
    glm::dvec3 centerMin{0.0}, centerMax{0.0}; ///< bounds of all slice centres
};

/// A placed slice: a square of side 2 radius centred at `center`, spanned by
/// `right` and `up`, with normal `tangent`; `thickness` is the length of yarn
/// it stands for; the cross-section is turned by `twistStep` radians at the next slice.
struct Slice {
    glm::dvec3 center, tangent, right, up;
    double thickness = 0.0;
    double twistStep = 0.0;
    std::uint32_t yarn = 0;
};

/// Plans the slices of a garment: slice counts, arc lengths and knot frames,
/// transported from knot to knot without flips. Throws yv::Error on a yarn
/// with fewer than 2 points or with repeated points that leave no tangent.
SlicePlan planSlices(const Garment& garment, const SliceOptions& options);

/// Slice `k` (0 <= k < sliceCount) of a segment. Slice k sits at the middle of
/// parameter interval [k/K, (k+1)/K]; its thickness is that interval's chord.
Slice placeSlice(const SegmentRecord& segment, std::uint32_t k, const SliceOptions& options);

/// Rotates v by the smallest rotation that takes unit vector `from` to unit vector `to`.
glm::dvec3 rotateMinimal(const glm::dvec3& v, const glm::dvec3& from, const glm::dvec3& to);

/// Fiber direction (unit, world space) at slice-local (x, y) from the twist
/// between this slice and the next (the paper's eq. 1), sign along the tangent.
glm::dvec3 fiberDirection(const Slice& slice, double x, double y);

} // namespace yv

// Uniform Catmull-Rom segments in the paper's matrix form (section 3.2). The
// evaluations are inline: slicing calls them for every slice (hundreds of
// millions at 50 slices a segment), and a call each cost more than its sums.
#pragma once

#include "garment/garment.h"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cmath>
#include <cstddef>

namespace yv {

/// The four control points P[i-1], P[i], P[i+1], P[i+2] that shape segment i
/// (from P[i] to P[i+1]). The curve passes through P[i] and P[i+1] with the
/// tangents (P[i+1]-P[i-1])/2 and (P[i+2]-P[i])/2.
using SegmentPoints = std::array<glm::dvec3, 4>;

/// Control points of segment `segment` of a yarn. Closed yarns wrap around.
/// Open yarns estimate their end tangents from the end chord: the missing
/// point is mirrored (P[-1] = 2 P[0] - P[1]), so the end tangent is P[1]-P[0].
/// A polyline uses mirrored points on both ends of every segment, which makes
/// the cubic a straight line with uniform speed. B-spline and Bezier segments
/// are converted exactly: the Catmull-Rom points of the same cubic polynomial
/// (same positions for every t), so the slicing and every backend need no
/// other basis. `segment` < yarnSegmentCount(yarn, type).
SegmentPoints segmentPoints(const Yarn& yarn, std::size_t segment, CurveType type);

/// Position at t in [0, 1]: 1/2 [1 t t^2 t^3] M [P[i-1] P[i] P[i+1] P[i+2]]^T.
inline glm::dvec3 evalCatmullRom(const SegmentPoints& p, double t) {
    // Rows of the paper's basis matrix M (times 1/2) applied to [1 t t^2 t^3].
    const double t2 = t * t, t3 = t2 * t;
    const double w0 = -t + 2.0 * t2 - t3;
    const double w1 = 2.0 - 5.0 * t2 + 3.0 * t3;
    const double w2 = t + 4.0 * t2 - 3.0 * t3;
    const double w3 = -t2 + t3;
    return 0.5 * (w0 * p[0] + w1 * p[1] + w2 * p[2] + w3 * p[3]);
}

/// Derivative with respect to t.
inline glm::dvec3 evalCatmullRomDerivative(const SegmentPoints& p, double t) {
    const double t2 = t * t;
    const double w0 = -1.0 + 4.0 * t - 3.0 * t2;
    const double w1 = -10.0 * t + 9.0 * t2;
    const double w2 = 1.0 + 8.0 * t - 9.0 * t2;
    const double w3 = -2.0 * t + 3.0 * t2;
    return 0.5 * (w0 * p[0] + w1 * p[1] + w2 * p[2] + w3 * p[3]);
}

/// Arc length of the curve for t in [t0, t1]: three-point Gauss-Legendre
/// quadrature of the speed (shaders/slice_placement.glsl: catmullRomArcLength).
inline double catmullRomArcLength(const SegmentPoints& p, double t0, double t1) {
    const double mid = 0.5 * (t0 + t1), half = 0.5 * (t1 - t0), node = std::sqrt(0.6) * half;
    return half * (5.0 / 9.0 * glm::length(evalCatmullRomDerivative(p, mid - node)) +
                   8.0 / 9.0 * glm::length(evalCatmullRomDerivative(p, mid)) +
                   5.0 / 9.0 * glm::length(evalCatmullRomDerivative(p, mid + node)));
}

/// Second derivative with respect to t.
inline glm::dvec3 evalCatmullRomSecondDerivative(const SegmentPoints& p, double t) {
    const double w0 = 4.0 - 6.0 * t;
    const double w1 = -10.0 + 18.0 * t;
    const double w2 = 8.0 - 18.0 * t;
    const double w3 = -2.0 + 6.0 * t;
    return 0.5 * (w0 * p[0] + w1 * p[1] + w2 * p[2] + w3 * p[3]);
}

/// Third derivative with respect to t (a cubic's is the same for every t).
glm::dvec3 evalCatmullRomThirdDerivative(const SegmentPoints& p);

/// Which way the curve leaves the segment's start (atEnd false: the limit of
/// the tangent as t falls to 0) or arrives at its end (atEnd true: as t rises
/// to 1), not normalized. That is the first derivative there; where it
/// vanishes (a cusp: the knot's neighbours coincide, so the curve stops there
/// and turns straight back), the first higher derivative that does not,
/// signed the way the curve moves. `cusp` is set when the first derivative
/// vanished. Zero only where the segment does not move at all. A derivative
/// counts as zero below 1e-12 of the size of the segment's end points.
glm::dvec3 knotDirection(const SegmentPoints& p, bool atEnd, bool* cusp = nullptr);

/// Exact bounding box of the segment for t in [0, 1]: the end points and, per
/// axis, the cubic's extrema (roots of its quadratic derivative) inside (0, 1).
void catmullRomBounds(const SegmentPoints& p, glm::dvec3& lo, glm::dvec3& hi);

} // namespace yv

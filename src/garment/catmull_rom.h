// Uniform Catmull-Rom segments in the paper's matrix form (section 3.2).
#pragma once

#include "garment/garment.h"

#include <glm/vec3.hpp>

#include <array>
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
glm::dvec3 evalCatmullRom(const SegmentPoints& p, double t);

/// Derivative with respect to t.
glm::dvec3 evalCatmullRomDerivative(const SegmentPoints& p, double t);

/// Arc length of the curve for t in [t0, t1]: three-point Gauss-Legendre
/// quadrature of the speed (shaders/common.glsl: catmullRomArcLength).
double catmullRomArcLength(const SegmentPoints& p, double t0, double t1);

/// Second derivative with respect to t.
glm::dvec3 evalCatmullRomSecondDerivative(const SegmentPoints& p, double t);

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

// A yarn-level garment: yarn centre curves through crossing points.
#pragma once

#include <glm/vec3.hpp>

#include <cstddef>
#include <vector>

namespace yv {

/// One yarn: the control points of a uniform Catmull-Rom curve through its
/// crossings (or a polyline). A closed yarn joins its last point to its first.
struct Yarn {
    std::vector<glm::dvec3> points;
    bool closed = false;
};

/// How the control points of a garment are meant to be joined. Catmull-Rom
/// is the paper's interpolation; a polyline is kept straight between points.
/// A uniform cubic B-spline approximates its control polygon (segment s of
/// an open curve is shaped by points s..s+3); a cubic Bezier curve passes
/// through every third point (segment s: points 3s..3s+3). See formats/bcc.md.
enum class CurveType { CatmullRom, Polyline, BSpline, Bezier };

/// Curve segments of a yarn of this type: n-1 (open) or n (closed) spans
/// between points for Catmull-Rom and polylines; n-3 or n for a B-spline;
/// (n-1)/3 or n/3 for Bezier curves. 0 when there are too few points.
inline std::size_t yarnSegmentCount(const Yarn& y, CurveType type) {
    const std::size_t n = y.points.size();
    switch (type) {
    case CurveType::BSpline: return y.closed ? (n >= 3 ? n : 0) : (n >= 4 ? n - 3 : 0);
    case CurveType::Bezier: return y.closed ? n / 3 : (n >= 4 ? (n - 1) / 3 : 0);
    default: return n < 2 ? 0 : (y.closed ? n : n - 1);
    }
}

struct Garment {
    std::vector<Yarn> yarns;
    CurveType curveType = CurveType::CatmullRom;
    /// Suggested yarn radius in world units (0: unknown, the caller decides).
    double yarnRadius = 0.0;

    std::size_t controlPointCount() const {
        std::size_t n = 0;
        for (const Yarn& y : yarns) n += y.points.size();
        return n;
    }
    /// Number of curve segments (yarnSegmentCount summed over the yarns).
    std::size_t segmentCount() const {
        std::size_t n = 0;
        for (const Yarn& y : yarns) n += yarnSegmentCount(y, curveType);
        return n;
    }
};

} // namespace yv

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
enum class CurveType { CatmullRom, Polyline };

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
    /// Number of curve segments: n-1 for an open yarn of n points, n for a closed one.
    std::size_t segmentCount() const {
        std::size_t n = 0;
        for (const Yarn& y : yarns)
            if (y.points.size() >= 2) n += y.closed ? y.points.size() : y.points.size() - 1;
        return n;
    }
};

} // namespace yv

#include "garment/catmull_rom.h"

#include "core/error.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace yv {

namespace {

/// The Catmull-Rom points of the cubic with end points a, b and end
/// derivatives da, db (cubic Hermite data): the curve passes through P1 and P2
/// with derivatives (P2-P0)/2 and (P3-P1)/2, and a cubic is fixed by its ends
/// and end derivatives, so every cubic segment has exactly one such form.
SegmentPoints fromHermite(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& da, const glm::dvec3& db) {
    return {b - 2.0 * da, a, b, a + 2.0 * db};
}

} // namespace

SegmentPoints segmentPoints(const Yarn& yarn, std::size_t segment, CurveType type) {
    const std::size_t n = yarn.points.size();
    YV_CHECK(segment < yarnSegmentCount(yarn, type));
    const auto& P = yarn.points;
    if (type == CurveType::BSpline) {
        // Uniform cubic B-spline on B0..B3: ends (B0 + 4 B1 + B2) / 6 and
        // (B1 + 4 B2 + B3) / 6, end derivatives (B2 - B0) / 2 and (B3 - B1) / 2.
        // A closed curve's segment s starts near point s, an open one's near s + 1.
        const std::size_t first = yarn.closed ? segment + n - 1 : segment;
        const glm::dvec3 b0 = P[first % n], b1 = P[(first + 1) % n], b2 = P[(first + 2) % n], b3 = P[(first + 3) % n];
        return fromHermite((b0 + 4.0 * b1 + b2) / 6.0, (b1 + 4.0 * b2 + b3) / 6.0, 0.5 * (b2 - b0), 0.5 * (b3 - b1));
    }
    if (type == CurveType::Bezier) {
        // Cubic Bezier on B0..B3: through B0 and B3, end derivatives 3 (B1 - B0) and 3 (B3 - B2).
        const std::size_t first = 3 * segment;
        const glm::dvec3 b0 = P[first], b1 = P[first + 1], b2 = P[first + 2], b3 = P[(first + 3) % n];
        return fromHermite(b0, b3, 3.0 * (b1 - b0), 3.0 * (b3 - b2));
    }

    const glm::dvec3 a = P[segment % n];
    const glm::dvec3 b = P[(segment + 1) % n];
    if (type == CurveType::Polyline) return {2.0 * a - b, a, b, 2.0 * b - a};

    glm::dvec3 before, after;
    if (yarn.closed) {
        before = P[(segment + n - 1) % n];
        after = P[(segment + 2) % n];
    } else {
        before = segment > 0 ? P[segment - 1] : 2.0 * a - b;
        after = segment + 2 < n ? P[segment + 2] : 2.0 * b - a;
    }
    return {before, a, b, after};
}

glm::dvec3 evalCatmullRomThirdDerivative(const SegmentPoints& p) {
    return 3.0 * (-p[0] + 3.0 * p[1] - 3.0 * p[2] + p[3]);
}

glm::dvec3 knotDirection(const SegmentPoints& p, bool atEnd, bool* cusp) {
    const double least = 1e-12 * (std::max(glm::length(p[1]), glm::length(p[2])) + 1.0);
    const double t = atEnd ? 1.0 : 0.0;
    const glm::dvec3 d1 = evalCatmullRomDerivative(p, t);
    const bool stops = !(glm::length(d1) > least);
    if (cusp) *cusp = stops;
    if (!stops) return d1;
    // C'(t + s) = C'(t) + s C''(t) + s^2 / 2 C''' with C'(t) gone: the tangent
    // as s -> 0 follows s C''(t), or C''' where that vanishes too. At the end
    // s is negative, so the curve arrives along -C''(1).
    const glm::dvec3 d2 = evalCatmullRomSecondDerivative(p, t);
    if (glm::length(d2) > least) return atEnd ? -d2 : d2;
    const glm::dvec3 d3 = evalCatmullRomThirdDerivative(p);
    return glm::length(d3) > least ? d3 : glm::dvec3(0.0);
}

void catmullRomBounds(const SegmentPoints& p, glm::dvec3& lo, glm::dvec3& hi) {
    lo = glm::min(p[1], p[2]);
    hi = glm::max(p[1], p[2]);
    for (int a = 0; a < 3; ++a) {
        // Derivative 0.5 (A t^2 + B t + C) from evalCatmullRomDerivative's weights.
        const double A = -3.0 * p[0][a] + 9.0 * p[1][a] - 9.0 * p[2][a] + 3.0 * p[3][a];
        const double B = 4.0 * p[0][a] - 10.0 * p[1][a] + 8.0 * p[2][a] - 2.0 * p[3][a];
        const double C = -p[0][a] + p[2][a];
        double roots[2];
        int n = 0;
        if (std::abs(A) < 1e-300) {
            if (B != 0.0) roots[n++] = -C / B;
        } else {
            const double disc = B * B - 4.0 * A * C;
            if (disc >= 0.0) {
                const double sq = std::sqrt(disc);
                roots[n++] = (-B - sq) / (2.0 * A);
                roots[n++] = (-B + sq) / (2.0 * A);
            }
        }
        for (int i = 0; i < n; ++i)
            if (roots[i] > 0.0 && roots[i] < 1.0) {
                const double v = evalCatmullRom(p, roots[i])[a];
                lo[a] = std::min(lo[a], v);
                hi[a] = std::max(hi[a], v);
            }
    }
}

} // namespace yv

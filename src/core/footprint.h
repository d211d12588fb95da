// A sample's footprint: the pixel square of the face, seen on the slice plane
// (a parallelogram), and how much of it the cross-section covers. Coverage
// rather than a point sample is what makes a boundary voxel read its true
// volume fraction and the mass exact for thin yarns. shaders/common.glsl
// mirrors these functions.
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>

namespace yv {

/// What diskCoverage finds of a parallelogram's edges before it looks at the
/// disk: found once for the many centres of a slice's same-shaped footprints.
struct FootprintShape {
    glm::dvec2 u, v;
    double area;  ///< |u x v|
    double reach; ///< half the sum of the edges' lengths: no point lies further from the centre
};

inline FootprintShape footprintShape(glm::dvec2 u, glm::dvec2 v) {
    return {u, v, std::abs(u.x * v.y - u.y * v.x), 0.5 * (glm::length(u) + glm::length(v))};
}

/// Area of (disk of radius r about the origin) ∩ (parallelogram centred at
/// `c` with the edges of `shape`), divided by the parallelogram's area.
/// Exact: the clipped polygon's area by the shoelace formula about `c` (no
/// cancellation however far the disk's centre is), plus a circular cap for
/// every arc of the boundary, r^2 / 2 (theta - sin theta), by its series when
/// theta is small.
inline double diskCoverage(glm::dvec2 c, const FootprintShape& shape, double r) {
    glm::dvec2 u = shape.u, v = shape.v;
    const double area = shape.area;
    if (!(area > 0.0)) return 0.0;
    const double reach = shape.reach, dist = glm::length(c);
    if (dist - reach >= r) return 0.0;
    if (dist + reach <= r) return 1.0;
    if (u.x * v.y - u.y * v.x < 0.0) std::swap(u, v); // counter-clockwise corners
    const glm::dvec2 corner[4] = {c - 0.5 * u - 0.5 * v, c + 0.5 * u - 0.5 * v, c + 0.5 * u + 0.5 * v,
                                  c - 0.5 * u + 0.5 * v};
    const double r2 = r * r;
    // Per edge, the part inside the disk: parameters [tIn, tOut] of [0, 1].
    double tIn[4], tOut[4];
    bool inside[4];
    for (int i = 0; i < 4; ++i) {
        const glm::dvec2 a = corner[i], d = corner[(i + 1) & 3] - a;
        const double qa = glm::dot(d, d), qb = glm::dot(a, d), qc = glm::dot(a, a) - r2;
        const double disc = qb * qb - qa * qc;
        const double s = std::sqrt(std::max(disc, 0.0));
        tIn[i] = std::max(0.0, (-qb - s) / qa);
        tOut[i] = std::min(1.0, (-qb + s) / qa);
        inside[i] = disc > 0.0 && tOut[i] > tIn[i];
    }
    // The clipped region's boundary, edge by edge: the edge's inside part
    // from its entry to its exit, then on to the entry of the next edge that
    // has an inside part: along the circle (an arc) where the edge leaves the
    // disk, or nothing where the next edge goes on inside from the shared
    // corner (which may lie on the circle). Written per edge with fixed indices
    // (no list of points) so that the shader's copy unrolls without a
    // dynamically indexed array; the sums are the same shoelace terms.
    double twice = 0.0, caps = 0.0;
    bool any = false;
    for (int i = 0; i < 4; ++i) {
        if (!inside[i]) continue;
        any = true;
        const int next = (i + 1) & 3;
        const glm::dvec2 a = corner[i], d = corner[next] - a;
        const glm::dvec2 entry = a + tIn[i] * d;
        glm::dvec2 nextEntry = entry; // the only edge inside: the arc closes on itself
        for (int step = 1; step < 4; ++step) {
            const int k = (i + step) & 3;
            if (inside[k]) {
                nextEntry = corner[k] + tIn[k] * (corner[(k + 1) & 3] - corner[k]);
                break;
            }
        }
        const bool exits = tOut[i] < 1.0 || !inside[next] || tIn[next] > 0.0;
        const glm::dvec2 exit = exits ? a + tOut[i] * d : nextEntry;
        const glm::dvec2 p = entry - c, q = exit - c, o = nextEntry - c;
        twice += (p.x * q.y - p.y * q.x) + (q.x * o.y - q.y * o.x);
        if (exits) {
            double theta = std::atan2(exit.x * nextEntry.y - exit.y * nextEntry.x, glm::dot(exit, nextEntry));
            // An exit and entry at one corner on the circle: no arc, whatever the rounding.
            if (theta < 0.0) theta = theta > -1e-9 ? 0.0 : theta + 2.0 * M_PI;
            const double t2 = theta * theta;
            const double excess = theta < 1e-2 ? theta * t2 / 6.0 * (1.0 - t2 / 20.0) : theta - std::sin(theta);
            caps += 0.5 * r2 * excess;
        }
    }
    if (!any) {
        // No corner inside and no crossing: the disk lies inside or outside.
        for (int i = 0; i < 4; ++i) {
            const glm::dvec2 e = corner[(i + 1) & 3] - corner[i];
            if (e.x * -corner[i].y - e.y * -corner[i].x < 0.0) return 0.0;
        }
        return std::min(1.0, M_PI * r2 / area);
    }
    return std::clamp((0.5 * twice + caps) / area, 0.0, 1.0);
}

/// The same, with edge vectors `u`, `v`.
inline double diskCoverage(glm::dvec2 c, glm::dvec2 u, glm::dvec2 v, double r) {
    return diskCoverage(c, footprintShape(u, v), r);
}

} // namespace yv

#include "garment/catmull_rom.h"

#include "core/error.h"

namespace yv {

SegmentPoints segmentPoints(const Yarn& yarn, std::size_t segment, CurveType type) {
    const std::size_t n = yarn.points.size();
    YV_CHECK(n >= 2);
    const auto& P = yarn.points;
    const glm::dvec3 a = P[segment % n];
    const glm::dvec3 b = P[(segment + 1) % n];
    if (type == CurveType::Polyline) return {2.0 * a - b, a, b, 2.0 * b - a};

    glm::dvec3 before, after;
    if (yarn.closed) {
        before = P[(segment + n - 1) % n];
        after = P[(segment + 2) % n];
    } else {
        YV_CHECK(segment + 1 < n);
        before = segment > 0 ? P[segment - 1] : 2.0 * a - b;
        after = segment + 2 < n ? P[segment + 2] : 2.0 * b - a;
    }
    return {before, a, b, after};
}

glm::dvec3 evalCatmullRom(const SegmentPoints& p, double t) {
    // Rows of the paper's basis matrix M (times 1/2) applied to [1 t t^2 t^3].
    const double t2 = t * t, t3 = t2 * t;
    const double w0 = -t + 2.0 * t2 - t3;
    const double w1 = 2.0 - 5.0 * t2 + 3.0 * t3;
    const double w2 = t + 4.0 * t2 - 3.0 * t3;
    const double w3 = -t2 + t3;
    return 0.5 * (w0 * p[0] + w1 * p[1] + w2 * p[2] + w3 * p[3]);
}

glm::dvec3 evalCatmullRomDerivative(const SegmentPoints& p, double t) {
    const double t2 = t * t;
    const double w0 = -1.0 + 4.0 * t - 3.0 * t2;
    const double w1 = -10.0 * t + 9.0 * t2;
    const double w2 = 1.0 + 8.0 * t - 9.0 * t2;
    const double w3 = -2.0 * t + 3.0 * t2;
    return 0.5 * (w0 * p[0] + w1 * p[1] + w2 * p[2] + w3 * p[3]);
}

} // namespace yv

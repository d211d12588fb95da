#include "garment/slices.h"

#include "core/error.h"

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace yv {
namespace {

glm::dvec3 anyPerpendicular(const glm::dvec3& t) {
    // Cross with the axis least aligned with t: never degenerate.
    const glm::dvec3 a = std::abs(t.x) <= std::abs(t.y) && std::abs(t.x) <= std::abs(t.z)
                             ? glm::dvec3(1, 0, 0)
                             : (std::abs(t.y) <= std::abs(t.z) ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1));
    return glm::normalize(glm::cross(t, a));
}

glm::dvec3 unitTangent(const SegmentPoints& p, double t, std::uint32_t yarn) {
    const glm::dvec3 d = evalCatmullRomDerivative(p, t);
    const double len = glm::length(d);
    if (!(len > 1e-12))
        throw Error("yarn " + std::to_string(yarn) + ": repeated control points leave the curve without a tangent");
    return d / len;
}

} // namespace

glm::dvec3 rotateMinimal(const glm::dvec3& v, const glm::dvec3& from, const glm::dvec3& to) {
    const double c = glm::dot(from, to);
    const glm::dvec3 k = glm::cross(from, to);
    if (c < -0.999999) {
        // Half turn: any axis perpendicular to `from` is minimal; pick a fixed one.
        const glm::dvec3 axis = anyPerpendicular(from);
        return 2.0 * glm::dot(axis, v) * axis - v;
    }
    // Rodrigues' formula with sin and (1 - cos) expressed through k and c.
    return v + glm::cross(k, v) + glm::cross(k, glm::cross(k, v)) / (1.0 + c);
}

SlicePlan planSlices(const Garment& garment, const SliceOptions& options) {
    if (options.slicesPerSegment < 1 && options.spacing <= 0.0)
        throw Error("slices per segment must be at least 1 (got " + std::to_string(options.slicesPerSegment) + ")");
    if (!(options.radius > 0.0)) throw Error("yarn radius must be positive");

    SlicePlan plan;
    plan.options = options;
    plan.segments.reserve(garment.segmentCount());
    for (std::size_t y = 0; y < garment.yarns.size(); ++y) {
        const Yarn& yarn = garment.yarns[y];
        if (yarn.points.size() < 2)
            throw Error("yarn " + std::to_string(y) + ": needs at least 2 control points, has " +
                        std::to_string(yarn.points.size()));
        const std::size_t segCount = yarn.closed ? yarn.points.size() : yarn.points.size() - 1;
        for (std::size_t s = 0; s < segCount; ++s) {
            SegmentRecord rec;
            rec.points = segmentPoints(yarn, s, garment.curveType);
            rec.yarn = static_cast<std::uint32_t>(y);
            plan.segments.push_back(rec);
        }
    }

    // Slice counts and chord lengths are independent per segment.
    tbb::parallel_for(std::size_t(0), plan.segments.size(), [&](std::size_t i) {
        SegmentRecord& rec = plan.segments[i];
        std::uint32_t k = static_cast<std::uint32_t>(options.slicesPerSegment);
        if (options.spacing > 0.0) {
            // Estimate the length from a fine chord sum, then choose K.
            double approx = 0.0;
            glm::dvec3 prev = evalCatmullRom(rec.points, 0.0);
            for (int j = 1; j <= 16; ++j) {
                const glm::dvec3 q = evalCatmullRom(rec.points, j / 16.0);
                approx += glm::length(q - prev);
                prev = q;
            }
            k = static_cast<std::uint32_t>(std::clamp(std::ceil(approx / options.spacing), 1.0, 1.0e6));
        }
        rec.sliceCount = k;
        double len = 0.0;
        glm::dvec3 prev = evalCatmullRom(rec.points, 0.0);
        for (std::uint32_t j = 1; j <= k; ++j) {
            const glm::dvec3 q = evalCatmullRom(rec.points, double(j) / k);
            len += glm::length(q - prev);
            prev = q;
        }
        rec.length = len;
    });

    // Arc lengths, slice offsets and knot frames run along each yarn in order.
    std::uint64_t firstSlice = 0;
    for (std::size_t i = 0; i < plan.segments.size(); ++i) {
        SegmentRecord& rec = plan.segments[i];
        const bool yarnStart = i == 0 || plan.segments[i - 1].yarn != rec.yarn;
        const glm::dvec3 t0 = unitTangent(rec.points, 0.0, rec.yarn);
        rec.knotTangent = t0;
        if (yarnStart) {
            rec.arcStart = 0.0;
            rec.knotUp = anyPerpendicular(t0);
        } else {
            const SegmentRecord& prevRec = plan.segments[i - 1];
            rec.arcStart = prevRec.arcStart + prevRec.length;
            // Parallel transport: the frame turns only as much as the tangent does.
            const glm::dvec3 up = rotateMinimal(prevRec.knotUp, prevRec.knotTangent, t0);
            rec.knotUp = glm::normalize(up - glm::dot(up, t0) * t0);
        }
        rec.firstSlice = firstSlice;
        firstSlice += rec.sliceCount;
    }
    plan.sliceCount = firstSlice;

    // Bounds of slice centres, per segment (for culling) and overall.
    tbb::parallel_for(std::size_t(0), plan.segments.size(), [&](std::size_t i) {
        SegmentRecord& rec = plan.segments[i];
        glm::dvec3 lo(HUGE_VAL), hi(-HUGE_VAL);
        for (std::uint32_t k = 0; k < rec.sliceCount; ++k) {
            const glm::dvec3 c = evalCatmullRom(rec.points, (k + 0.5) / rec.sliceCount);
            lo = glm::min(lo, c);
            hi = glm::max(hi, c);
        }
        rec.centerMin = lo;
        rec.centerMax = hi;
    });
    glm::dvec3 lo(HUGE_VAL), hi(-HUGE_VAL);
    for (const SegmentRecord& rec : plan.segments) {
        lo = glm::min(lo, rec.centerMin);
        hi = glm::max(hi, rec.centerMax);
    }
    plan.centerMin = lo;
    plan.centerMax = hi;
    return plan;
}

Slice placeSlice(const SegmentRecord& segment, std::uint32_t k, const SliceOptions& options) {
    const double invK = 1.0 / segment.sliceCount;
    const double t = (k + 0.5) * invK;
    Slice s;
    s.yarn = segment.yarn;
    s.center = evalCatmullRom(segment.points, t);
    s.tangent = unitTangent(segment.points, t, segment.yarn);
    s.thickness = glm::length(evalCatmullRom(segment.points, (k + 1) * invK) -
                              evalCatmullRom(segment.points, k * invK));
    s.twistStep = options.twist * s.thickness;

    glm::dvec3 up = rotateMinimal(segment.knotUp, segment.knotTangent, s.tangent);
    up = glm::normalize(up - glm::dot(up, s.tangent) * s.tangent);
    // Twist phase grows with arc length; within a segment arc length is taken
    // as linear in t, the same rule the vertex shader uses.
    const double phase = options.twist * (segment.arcStart + t * segment.length);
    const glm::dvec3 side = glm::cross(s.tangent, up);
    s.right = std::cos(phase) * up + std::sin(phase) * side;
    s.up = glm::cross(s.tangent, s.right);
    return s;
}

glm::dvec3 fiberDirection(const Slice& slice, double x, double y) {
    // Eq. 1: the fibre at (x, y) sits at (x, y) turned by the twist step on the
    // next slice, one thickness further along the tangent.
    const double c = std::cos(slice.twistStep), s = std::sin(slice.twistStep);
    const double dx = x * c - y * s - x;
    const double dy = x * s + y * c - y;
    return glm::normalize(dx * slice.right + dy * slice.up + slice.thickness * slice.tangent);
}

} // namespace yv

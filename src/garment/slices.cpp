#include "garment/slices.h"

#include "core/error.h"
#include "garment/slice_measures.h"

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <span>
#include <string>
#include <utility>

namespace yv {
namespace {

glm::dvec3 anyPerpendicular(const glm::dvec3& t) {
    // Cross with the axis least aligned with t: never degenerate.
    const glm::dvec3 a = std::abs(t.x) <= std::abs(t.y) && std::abs(t.x) <= std::abs(t.z)
                             ? glm::dvec3(1, 0, 0)
                             : (std::abs(t.y) <= std::abs(t.z) ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1));
    return glm::normalize(glm::cross(t, a));
}


Error noTangent(std::uint32_t yarn) {
    return Error("yarn " + std::to_string(yarn) + ": repeated control points leave the curve without a tangent");
}

/// The unit tangent from the curve's derivative `d` at a point of `yarn`.
glm::dvec3 unitTangent(const glm::dvec3& d, std::uint32_t yarn) {
    const double len = glm::length(d);
    if (!(len > kLeastCurveSpeed)) throw noTangent(yarn);
    return d / len;
}

/// Arc lengths, parallel-transported knot frames and twist phases of one
/// yarn's segments (slice counts and lengths already set). An open yarn turns
/// at the requested rate. A closed yarn must come back to its first frame:
/// transport brings the frame back turned by the holonomy angle, so the rate
/// becomes the one nearest the requested rate whose turn over the loop
/// cancels it, in whole turns.
void frameAndTwistYarn(const Yarn& yarn, double twist, std::span<SegmentRecord> segments) {
    for (std::size_t i = 0; i < segments.size(); ++i) {
        SegmentRecord& rec = segments[i];
        // At a cusp (the curve turns straight back at the knot) the frame
        // starts from the tangent the curve leaves the knot by.
        const glm::dvec3 t0 = unitTangent(knotDirection(rec.points, false), rec.yarn);
        rec.knotTangent = t0;
        if (i == 0) {
            rec.arcStart = 0.0;
            rec.knotUp = anyPerpendicular(t0);
        } else {
            const SegmentRecord& prevRec = segments[i - 1];
            rec.arcStart = prevRec.arcStart + prevRec.length;
            // Parallel transport: the frame turns only as much as the tangent does.
            const glm::dvec3 up = rotateMinimal(prevRec.knotUp, prevRec.knotTangent, t0);
            rec.knotUp = glm::normalize(up - glm::dot(up, t0) * t0);
        }
    }
    const SegmentRecord& head = segments.front();
    const SegmentRecord& tail = segments.back();
    const double loopLength = tail.arcStart + tail.length;
    double rate = twist;
    if (yarn.closed && loopLength > 0.0) {
        glm::dvec3 back = rotateMinimal(tail.knotUp, tail.knotTangent, head.knotTangent);
        back = glm::normalize(back - glm::dot(back, head.knotTangent) * head.knotTangent);
        const double holonomy =
            std::atan2(glm::dot(head.knotTangent, glm::cross(head.knotUp, back)), glm::dot(head.knotUp, back));
        const double turns = std::round((twist * loopLength + holonomy) / (2.0 * M_PI));
        rate = (2.0 * M_PI * turns - holonomy) / loopLength;
    }
    for (SegmentRecord& rec : segments) {
        rec.twistRate = rate;
        // Kept in [0, 2 pi) so that float shaders lose no precision on long yarns.
        const double phase = std::fmod(rate * rec.arcStart, 2.0 * M_PI);
        rec.phaseStart = phase < 0.0 ? phase + 2.0 * M_PI : phase;
    }
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

namespace {

/// One segment's slice count (from the spacing where one is asked for) and
/// what measureSlices finds of its slices: length, bounds of the slice
/// centres, reach and the tangents' mean largest component. Returns the
/// largest slice thickness; `flat`: a slice has no tangent (repeated
/// control points).
double measureSegment(SegmentRecord& rec, const SliceOptions& options, double halfDiagonal, bool& flat) {
    std::uint32_t k = static_cast<std::uint32_t>(options.slicesPerSegment);
    if (options.spacing > 0.0) {
        // Slices sit at uniform t, and the curve's speed varies along a
        // segment: K from the fastest part (sampled at 17 points) keeps
        // every slice's thickness within the spacing.
        const double fastest = fastestCurveSpeed(rec.points);
        k = static_cast<std::uint32_t>(std::clamp(std::ceil(fastest / options.spacing * (1.0 - 1e-12)), 1.0, 1.0e6));
    }
    rec.sliceCount = k;
    const SegmentMeasures m = measureSlices(rec, halfDiagonal);
    rec.length = m.length;
    rec.centerMin = m.centerMin;
    rec.centerMax = m.centerMax;
    rec.reach = m.reach;
    rec.meanDominant = m.dominantSum / k;
    flat = flat || m.flat;
    return m.spacing;
}

/// The plan's bounds of slice centres, largest reach and largest spacing.
struct Extremes {
    glm::dvec3 lo{HUGE_VAL}, hi{-HUGE_VAL};
    double reach = 0.0, spacing = 0.0;
};

/// Over every segment, on every core: min and max are exact, so any split
/// gives the same answers.
Extremes planExtremes(std::span<const SegmentRecord> segments, const std::vector<double>& spacingOf) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, segments.size()), Extremes{},
        [&](const tbb::blocked_range<std::size_t>& range, Extremes acc) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
                const SegmentRecord& rec = segments[i];
                acc.lo = glm::min(acc.lo, rec.centerMin);
                acc.hi = glm::max(acc.hi, rec.centerMax);
                acc.reach = std::max(acc.reach, rec.reach);
                acc.spacing = std::max(acc.spacing, spacingOf[i]);
            }
            return acc;
        },
        [](const Extremes& a, const Extremes& b) {
            return Extremes{glm::min(a.lo, b.lo), glm::max(a.hi, b.hi), std::max(a.reach, b.reach),
                            std::max(a.spacing, b.spacing)};
        });
}

} // namespace

SlicePlan planSlices(const Garment& garment, const SliceOptions& options) {
    glm::dvec3 curveMin, curveMax;
    curveBounds(garment, curveMin, curveMax);
    return planSlices(garment, options, curveMin, curveMax);
}

SlicePlan planSlices(const Garment& garment, const SliceOptions& options, const glm::dvec3& curveMin,
                     const glm::dvec3& curveMax) {
    if (options.slicesPerSegment < 1 && options.spacing <= 0.0)
        throw Error("slices per segment must be at least 1 (got " + std::to_string(options.slicesPerSegment) + ")");
    if (!(options.radius > 0.0)) throw Error("yarn radius must be positive");

    SlicePlan plan;
    plan.options = options;
    // Segments are counted per yarn first, so that each yarn fills its own
    // records on every core (the records of a large garment are hundreds of MB).
    std::vector<std::size_t> yarnFirst(garment.yarns.size() + 1, 0);
    for (std::size_t y = 0; y < garment.yarns.size(); ++y) {
        const Yarn& yarn = garment.yarns[y];
        const std::size_t segCount = yarnSegmentCount(yarn, garment.curveType);
        if (segCount == 0)
            throw Error("yarn " + std::to_string(y) + ": " + std::to_string(yarn.points.size()) +
                        " control points make no curve segment (at least 2 are needed; 4 for an open B-spline or Bezier curve)");
        yarnFirst[y + 1] = yarnFirst[y] + segCount;
    }
    plan.segments.resize(yarnFirst.back());
    const auto eachYarn = [&](auto&& body) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, garment.yarns.size()), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t y = r.begin(); y != r.end(); ++y) body(y, yarnFirst[y], yarnFirst[y + 1]);
        });
    };
    eachYarn([&](std::size_t y, std::size_t first, std::size_t end) {
        for (std::size_t i = first; i < end; ++i) {
            plan.segments[i] = SegmentRecord{};
            plan.segments[i].points = segmentPoints(garment.yarns[y], i - first, garment.curveType);
            plan.segments[i].yarn = static_cast<std::uint32_t>(y);
        }
    });

    // Per segment, independently: its slices, length, bounds (for culling)
    // and reach (measureSegment).
    const double halfDiagonal = options.radius * std::sqrt(2.0);
    std::vector<double> spacingOf(plan.segments.size(), 0.0);
    // A slice without a tangent (repeated control points) is reported after
    // the knots' frames are, as placeSlice would report it.
    std::atomic<std::size_t> firstFlatSegment{plan.segments.size()};
    tbb::parallel_for(std::size_t(0), plan.segments.size(), [&](std::size_t i) {
        bool flat = false;
        spacingOf[i] = measureSegment(plan.segments[i], options, halfDiagonal, flat);
        if (flat) {
            std::size_t seen = firstFlatSegment.load();
            while (i < seen && !firstFlatSegment.compare_exchange_weak(seen, i)) {}
        }
    });

    // Slice offsets run over the whole garment; the same pass sums what the
    // plan's users would each find with a pass of their own over a few
    // hundred MB of records.
    std::uint64_t firstSlice = 0;
    plan.fewestSlices = plan.segments.empty() ? 0 : ~0u;
    for (SegmentRecord& rec : plan.segments) {
        rec.firstSlice = firstSlice;
        firstSlice += rec.sliceCount;
        plan.yarnLength += rec.length;
        plan.fewestSlices = std::min(plan.fewestSlices, rec.sliceCount);
        plan.mostSlices = std::max(plan.mostSlices, rec.sliceCount);
    }
    plan.sliceCount = firstSlice;

    // Arc lengths, knot frames and the twist run along each yarn in order,
    // yarns side by side. A yarn without a tangent is reported as the serial
    // loop would: the first such yarn, whichever core found it.
    std::atomic<std::size_t> firstBadYarn{garment.yarns.size()};
    eachYarn([&](std::size_t y, std::size_t first, std::size_t end) {
        try {
            frameAndTwistYarn(garment.yarns[y], options.twist, std::span(plan.segments).subspan(first, end - first));
        } catch (const Error&) {
            std::size_t seen = firstBadYarn.load();
            while (y < seen && !firstBadYarn.compare_exchange_weak(seen, y)) {}
        }
    });
    if (const std::size_t bad = firstBadYarn.load(); bad < garment.yarns.size())
        frameAndTwistYarn(garment.yarns[bad], options.twist, std::span(plan.segments).subspan(yarnFirst[bad], yarnFirst[bad + 1] - yarnFirst[bad]));

    if (const std::size_t flat = firstFlatSegment.load(); flat < plan.segments.size())
        throw noTangent(plan.segments[flat].yarn);
    const Extremes all = planExtremes(plan.segments, spacingOf);
    plan.centerMin = all.lo;
    plan.centerMax = all.hi;
    plan.maxReach = all.reach;
    plan.maxSpacing = all.spacing;
    plan.curveMin = curveMin;
    plan.curveMax = curveMax;
    return plan;
}

void curveBounds(const Garment& garment, glm::dvec3& lo, glm::dvec3& hi) {
    // Yarns on every core (min and max are exact, so any split gives the same box).
    using Box = std::pair<glm::dvec3, glm::dvec3>;
    const Box empty{glm::dvec3(HUGE_VAL), glm::dvec3(-HUGE_VAL)};
    const Box box = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, garment.yarns.size()), empty,
        [&](const tbb::blocked_range<std::size_t>& range, Box acc) {
            for (std::size_t y = range.begin(); y != range.end(); ++y) {
                const Yarn& yarn = garment.yarns[y];
                const std::size_t segCount = yarnSegmentCount(yarn, garment.curveType);
                for (std::size_t s = 0; s < segCount; ++s) {
                    glm::dvec3 a, b;
                    catmullRomBounds(segmentPoints(yarn, s, garment.curveType), a, b);
                    acc.first = glm::min(acc.first, a);
                    acc.second = glm::max(acc.second, b);
                }
            }
            return acc;
        },
        [](const Box& a, const Box& b) { return Box{glm::min(a.first, b.first), glm::max(a.second, b.second)}; });
    lo = box.first;
    hi = box.second;
}

SliceOnCurve sliceOnCurve(const SegmentRecord& segment, std::uint32_t k) {
    const double invK = 1.0 / segment.sliceCount;
    const double t = (k + 0.5) * invK;
    SliceOnCurve g;
    g.center = evalCatmullRom(segment.points, t);
    g.derivative = evalCatmullRomDerivative(segment.points, t);
    g.thickness = catmullRomArcLength(segment.points, k * invK, (k + 1) * invK);
    const double speed = glm::length(g.derivative);
    g.hasTangent = speed > kLeastCurveSpeed;
    if (!g.hasTangent) return g;
    g.tangent = g.derivative / speed;
    const glm::dvec3 d2 = evalCatmullRomSecondDerivative(segment.points, t);
    g.curvature = (d2 - glm::dot(d2, g.tangent) * g.tangent) / glm::dot(g.derivative, g.derivative);
    return g;
}

Slice placeSlice(const SegmentRecord& segment, std::uint32_t k) {
    const SliceOnCurve g = sliceOnCurve(segment, k);
    Slice s;
    s.yarn = segment.yarn;
    s.center = g.center;
    if (!g.hasTangent) throw noTangent(segment.yarn);
    s.tangent = g.tangent;
    s.thickness = g.thickness;
    s.twistStep = segment.twistRate * s.thickness;
    s.curvature = g.curvature;

    glm::dvec3 up = rotateMinimal(segment.knotUp, segment.knotTangent, s.tangent);
    up = glm::normalize(up - glm::dot(up, s.tangent) * s.tangent);
    // Twist phase grows with arc length; within a segment arc length is taken
    // as linear in t, the same rule the vertex shader uses.
    const double t = (k + 0.5) * (1.0 / segment.sliceCount);
    const double phase = segment.phaseStart + segment.twistRate * t * segment.length;
    const glm::dvec3 side = glm::cross(s.tangent, up);
    s.right = std::cos(phase) * up + std::sin(phase) * side;
    s.up = glm::cross(s.tangent, s.right);
    return s;
}

FiberTwist fiberTwist(const Slice& slice) { return {std::cos(slice.twistStep), std::sin(slice.twistStep)}; }

glm::dvec3 fiberDirection(const Slice& slice, double x, double y) { return fiberDirection(slice, fiberTwist(slice), x, y); }

glm::dvec3 fiberDirection(const Slice& slice, const FiberTwist& twist, double x, double y) {
    // Eq. 1: the fibre at (x, y) sits at (x, y) turned by the twist step on the
    // next slice, one thickness further along the tangent.
    const double c = twist.cos, s = twist.sin;
    const double dx = x * c - y * s - x;
    const double dy = x * s + y * c - y;
    return glm::normalize(dx * slice.right + dy * slice.up + slice.thickness * slice.tangent);
}

} // namespace yv

#include "garment/curve_check.h"

#include "core/error.h"
#include "core/world_units.h"
#include "garment/catmull_rom.h"

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <string>

namespace yv {
namespace {

/// A span this many times the curve's median span is worth a warning: real
/// garments keep spans within a few times of each other, and a closed flag
/// on an open yarn joins its ends with a chord across the garment.
constexpr double kLongSpanFactor = 20.0;
/// Warnings printed one per curve up to this many, then a count.
constexpr std::size_t kMaxLongSpanLines = 5;

std::string curveText(const std::string& name, std::size_t curve) {
    return name + ": curve " + std::to_string(curve);
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
}

/// Removes points equal to their predecessor (and, on a closed curve, a last
/// point equal to the first). `original` keeps each point's index in the file.
void dropRepeats(Yarn& yarn, bool interior, std::vector<std::size_t>& original, CurveCheckReport& report) {
    std::vector<glm::dvec3> kept;
    std::vector<std::size_t> keptIndex;
    kept.reserve(yarn.points.size());
    for (std::size_t j = 0; j < yarn.points.size(); ++j) {
        if (interior && !kept.empty() && yarn.points[j] == kept.back()) {
            ++report.droppedSpans;
            continue;
        }
        kept.push_back(yarn.points[j]);
        keptIndex.push_back(j);
    }
    while (yarn.closed && kept.size() >= 2 && kept.back() == kept.front() &&
           (interior || kept.size() % 3 == 1)) {
        kept.pop_back();
        keptIndex.pop_back();
        ++report.droppedSpans;
        ++report.droppedClosingSpans;
    }
    yarn.points = std::move(kept);
    original = std::move(keptIndex);
}

/// Refuses a point count the curve type cannot use.
void checkCount(const Yarn& yarn, CurveType type, std::size_t filePoints, const std::string& where) {
    const std::size_t n = yarn.points.size();
    if (n < 2 || (n == 2 && yarn.closed && type != CurveType::Polyline))
        throw Error(where + ": all " + std::to_string(filePoints) + " control points lie at " +
                    (n < 2 ? "one place (point 0)" : "two places, a closed curve that only goes back and forth") +
                    ": not a curve");
    if (type == CurveType::BSpline && !yarn.closed && n < 4)
        throw Error(where + ": an open B-spline needs at least 4 control points, has " + std::to_string(n));
    if (type == CurveType::Bezier && (yarn.closed ? n % 3 != 0 : (n < 4 || n % 3 != 1)))
        throw Error(where + ": " + std::to_string(n) + " control points cannot make a cubic Bezier curve: it needs 3k+1 " +
                    "(open) or 3k (closed: the last segment ends at the first point)");
}

/// The file index of the knot at one end of segment `s`: for Catmull-Rom and
/// polylines the segment's start or end point; for B-splines and Bezier
/// curves the segment's first control point is as close as one can name it.
std::size_t knotPoint(const Yarn& yarn, CurveType type, std::size_t s, int end, const std::vector<std::size_t>& original) {
    const std::size_t n = yarn.points.size();
    const std::size_t local = type == CurveType::Bezier    ? (3 * s + 3 * end) % n
                              : type == CurveType::BSpline ? (yarn.closed ? s + n - 1 + end : s + end) % n
                                                           : (s + end) % n;
    return original[local];
}

/// The knots (file indices, ascending, each once) where the curve's
/// derivative vanishes: cusps, where the knot's neighbours coincide and the
/// curve turns straight back. The slicer takes each side's one-sided
/// tangent there (knotDirection). Refuses a segment that does not move at
/// all: its slices would have no normal.
std::vector<std::size_t> findCusps(const Yarn& yarn, CurveType type, const std::vector<std::size_t>& original,
                                   const std::string& where) {
    std::vector<std::size_t> cusps;
    const std::size_t segments = yarnSegmentCount(yarn, type);
    for (std::size_t s = 0; s < segments; ++s) {
        const SegmentPoints p = segmentPoints(yarn, s, type);
        for (int end = 0; end < 2; ++end) {
            bool cusp = false;
            if (knotDirection(p, end == 1, &cusp) == glm::dvec3(0.0))
                throw Error(where + " point " + std::to_string(knotPoint(yarn, type, s, end, original)) +
                            ": the curve does not move from there (the control points of its segment coincide): not a curve");
            if (cusp) cusps.push_back(knotPoint(yarn, type, s, end, original));
        }
    }
    std::sort(cusps.begin(), cusps.end());
    cusps.erase(std::unique(cusps.begin(), cusps.end()), cusps.end());
    return cusps;
}

/// The warning for a span far longer than the curve's median span, or "".
std::string longSpanWarning(const Yarn& yarn, CurveType type, const std::vector<std::size_t>& original,
                            const std::string& where) {
    const std::size_t n = yarn.points.size();
    const std::size_t spans = yarn.closed ? n : n - 1;
    if (spans < 4 || type == CurveType::Bezier) return {}; // Bezier handles are not spans of the curve
    std::vector<double> length(spans);
    for (std::size_t j = 0; j < spans; ++j) length[j] = glm::length(yarn.points[(j + 1) % n] - yarn.points[j]);
    const double typical = median(length);
    const std::size_t worst = std::max_element(length.begin(), length.end()) - length.begin();
    if (!(length[worst] > kLongSpanFactor * typical)) return {};
    const bool closing = yarn.closed && worst == n - 1;
    return where + ": the span from point " + std::to_string(original[worst]) + " to point " +
           std::to_string(original[(worst + 1) % n]) + " is " + numberText(length[worst]) + " long, " +
           numberText(length[worst] / typical) + " times the curve's median span " + numberText(typical) +
           (closing ? " (the closing span of a closed curve: is the closed flag right?)" : "");
}

/// What checking one curve found; curves are checked side by side and their
/// findings taken in file order, so the report is the same on any core count.
struct CurveFinding {
    CurveCheckReport dropped; ///< its dropped spans (no warnings)
    std::string error;        ///< why the curve cannot be used, or ""
    std::string longSpan;     ///< longSpanWarning's text, or ""
    std::vector<std::size_t> cusps; ///< findCusps's knots
};

/// One line for every cusp of the garment ("" when there is none): the
/// point when there is one, else the count and the first in file order.
std::string cuspWarning(const std::string& name, const std::vector<CurveFinding>& findings, std::size_t& count) {
    count = 0;
    std::string first;
    for (std::size_t i = 0; i < findings.size(); ++i) {
        if (first.empty() && !findings[i].cusps.empty())
            first = "curve " + std::to_string(i) + " point " + std::to_string(findings[i].cusps.front());
        count += findings[i].cusps.size();
    }
    if (count == 0) return {};
    if (count == 1)
        return name + ": " + first + ": the curve stops there and turns straight back (its neighbours coincide: no " +
               "tangent); voxelized as a cusp, each side along its own tangent";
    return name + ": " + std::to_string(count) + " points where a curve stops and turns straight back (their neighbours " +
           "coincide: no tangent), the first at " + first + "; voxelized as cusps, each side along its own tangent";
}

} // namespace

std::string CurveCheckReport::droppedText(const std::string& name) const {
    if (droppedSpans == 0) return {};
    std::string s = name + ": dropped " + std::to_string(droppedSpans) + " zero-length span" +
                    (droppedSpans == 1 ? "" : "s") + " (repeated control points";
    if (droppedClosingSpans > 0)
        s += "; " + std::to_string(droppedClosingSpans) + " of them closing closed curves whose last point repeats the first";
    return s + ")";
}

CurveCheckReport checkCurves(Garment& garment, const std::string& name) {
    // Interior repeats are zero-length spans only where spans join consecutive
    // points; a B-spline's double point is a legitimate, still moving, curve.
    const bool interior = garment.curveType == CurveType::CatmullRom || garment.curveType == CurveType::Polyline;
    const bool closing = interior || garment.curveType == CurveType::Bezier;
    std::vector<CurveFinding> findings(garment.yarns.size());
    tbb::parallel_for(std::size_t(0), garment.yarns.size(), [&](std::size_t i) {
        Yarn& yarn = garment.yarns[i];
        CurveFinding& found = findings[i];
        const std::string where = curveText(name, i);
        const std::size_t filePoints = yarn.points.size();
        std::vector<std::size_t> original;
        if (closing) {
            dropRepeats(yarn, interior, original, found.dropped);
        } else {
            original.resize(filePoints);
            for (std::size_t j = 0; j < filePoints; ++j) original[j] = j;
        }
        try {
            checkCount(yarn, garment.curveType, filePoints, where);
            found.cusps = findCusps(yarn, garment.curveType, original, where);
        } catch (const Error& e) {
            found.error = e.what();
            return;
        }
        found.longSpan = longSpanWarning(yarn, garment.curveType, original, where);
    });

    for (const CurveFinding& found : findings)
        if (!found.error.empty()) throw Error(found.error); // the first curve that cannot be used
    CurveCheckReport report;
    if (std::string cusps = cuspWarning(name, findings, report.cusps); !cusps.empty()) report.warnings.push_back(cusps);
    std::size_t curvesWithLongSpans = 0;
    for (const CurveFinding& found : findings) {
        report.droppedSpans += found.dropped.droppedSpans;
        report.droppedClosingSpans += found.dropped.droppedClosingSpans;
        if (!found.longSpan.empty() && ++curvesWithLongSpans <= kMaxLongSpanLines) report.warnings.push_back(found.longSpan);
    }
    if (curvesWithLongSpans > kMaxLongSpanLines)
        report.warnings.push_back(name + ": " + std::to_string(curvesWithLongSpans - kMaxLongSpanLines) +
                                  " more curves have a span over " + numberText(kLongSpanFactor) +
                                  " times their median span");
    return report;
}

} // namespace yv

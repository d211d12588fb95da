#include "garment/slice_measures.h"

#include "core/cpu_features.h"
#include "core/double_lanes.h"
#include "garment/slice_lanes.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace yv {

namespace lanes {
/// Four slices in AVX (slice_measures_avx.cpp, built with -mavx): only call where cpuHasAvx().
void measureSliceLanesAvx(const double (&p)[4][3], std::uint32_t count, std::uint32_t first, double halfDiagonal,
                          double (&out)[4][kSliceMeasureValues]);
/// Eight slices in two independent AVX chains (their divisions and square
/// roots overlap): only call where cpuHasAvx().
void measureSliceLanesAvxPair(const double (&p)[4][3], std::uint32_t count, std::uint32_t first, double halfDiagonal,
                              double (&out)[8][kSliceMeasureValues]);
/// The fastest of a segment's first groups * 4 speeds in AVX: only call where cpuHasAvx().
double fastestSpeedLanesAvx(const double (&p)[4][3], std::uint32_t groups);
/// The voxels of four slices' centres in AVX: only call where cpuHasAvx().
void sliceVoxelLanesAvx(const double (&p)[4][3], std::uint32_t count, std::uint32_t first, const double (&origin)[3],
                        double invVoxelSize, double (&out)[4][kSliceVoxelValues]);
} // namespace lanes

namespace {

/// Adds one slice to the measures, in slice order (the length is a sum).
/// `moves`: the curve has a tangent there (else `reach` and `dominant` are meaningless).
void addSlice(SegmentMeasures& m, const glm::dvec3& centre, double thickness, bool moves, double reach,
              double dominant) {
    m.length += thickness;
    m.centerMin = glm::min(m.centerMin, centre);
    m.centerMax = glm::max(m.centerMax, centre);
    m.spacing = std::max(m.spacing, thickness);
    if (!moves) {
        m.flat = true;
        return;
    }
    m.reach = std::max(m.reach, reach);
    m.dominantSum += dominant;
}

/// Slice k one at a time, through sliceOnCurve.
void addScalar(SegmentMeasures& m, const SegmentRecord& segment, std::uint32_t k, double halfDiagonal) {
    const SliceOnCurve g = sliceOnCurve(segment, k);
    double reach = 0.0, dominant = 0.0;
    if (g.hasTangent) {
        const glm::dvec3 t = glm::abs(g.tangent);
        dominant = std::max({t.x, t.y, t.z});
        const double depth = (1.0 + glm::length(g.curvature) * halfDiagonal) * g.thickness / dominant;
        reach = halfDiagonal + 0.5 * depth;
    }
    addSlice(m, g.center, g.thickness, g.hasTangent, reach, dominant);
}

void segmentPointsOf(const SegmentRecord& segment, double (&p)[4][3]) {
    for (int i = 0; i < 4; ++i)
        for (int a = 0; a < 3; ++a) p[i][a] = segment.points[i][a];
}

/// Groups of `width` slices from slice `k` up to `end`, each group through
/// `kernel(p, first, out)` (out: double[width][values]) and each slice's
/// values handed to `take(slice, values)` in order. A last group cut short
/// by `end` is measured whole, its lanes past `end` (slices past the
/// segment's last, or a run's) left untaken: a short segment's last slices
/// took longer one at a time than a whole group. Returns `end`.
template <int width, int values, class Kernel, class Take>
std::uint32_t inGroups(const SegmentRecord& segment, std::uint32_t k, std::uint32_t end, Kernel&& kernel, Take&& take) {
    double p[4][3];
    segmentPointsOf(segment, p);
    for (; k < end; k += width) {
        double out[width][values];
        kernel(p, k, out);
        const std::uint32_t taken = std::min<std::uint32_t>(width, end - k);
        for (std::uint32_t l = 0; l < taken; ++l) take(k + l, out[l]);
    }
    return end;
}

/// inGroups in AVX's four lanes where `lanes` allows them, else in SSE2's
/// two; returns the first slice not done (the caller does the rest one at a
/// time: all of them with SliceLanes::Scalar).
template <int values, class AvxKernel, class Sse2Kernel, class Take>
std::uint32_t inLanes(const SegmentRecord& segment, std::uint32_t k, std::uint32_t end, SliceLanes lanes,
                      AvxKernel&& avx, Sse2Kernel&& sse2, Take&& take) {
#if defined(__x86_64__) || defined(__i386__)
    if (lanes == SliceLanes::Avx || (lanes == SliceLanes::Auto && cpuHasAvx()))
        return inGroups<4, values>(segment, k, end, avx, take);
#endif
#if defined(__SSE2__)
    if (lanes != SliceLanes::Scalar) k = inGroups<2, values>(segment, k, end, sse2, take);
#endif
    return k;
}

/// inLanes through measureSliceLanes.
template <class Take>
std::uint32_t measureInLanes(const SegmentRecord& segment, double halfDiagonal, std::uint32_t k, std::uint32_t end,
                             SliceLanes lanes, Take&& take) {
    const std::uint32_t count = segment.sliceCount;
#if defined(__x86_64__) || defined(__i386__)
    // Whole groups of eight first, where the segment has them (the paper's 50 slices a segment).
    if (lanes == SliceLanes::Avx || (lanes == SliceLanes::Auto && cpuHasAvx()))
        k = inGroups<8, lanes::kSliceMeasureValues>(
            segment, k, k + (end - k) / 8 * 8,
            [&](const double (&p)[4][3], std::uint32_t first, double (&out)[8][lanes::kSliceMeasureValues]) {
                lanes::measureSliceLanesAvxPair(p, count, first, halfDiagonal, out);
            },
            take);
#endif
    return inLanes<lanes::kSliceMeasureValues>(
        segment, k, end, lanes,
        [&](const double (&p)[4][3], std::uint32_t first, double (&out)[4][lanes::kSliceMeasureValues]) {
            lanes::measureSliceLanesAvx(p, count, first, halfDiagonal, out);
        },
        [&](const double (&p)[4][3], std::uint32_t first, double (&out)[2][lanes::kSliceMeasureValues]) {
            lanes::measureSliceLanes<lanes::Sse2Lanes>(p, count, first, halfDiagonal, out);
        },
        take);
}

} // namespace

SegmentMeasures measureSlices(const SegmentRecord& segment, double halfDiagonal, SliceLanes lanes) {
    SegmentMeasures m;
    m.reach = halfDiagonal;
    m.centerMin = glm::dvec3(HUGE_VAL);
    m.centerMax = glm::dvec3(-HUGE_VAL);
    const std::uint32_t done =
        measureInLanes(segment, halfDiagonal, 0, segment.sliceCount, lanes, [&](std::uint32_t, const double* v) {
            addSlice(m, glm::dvec3(v[0], v[1], v[2]), v[3], v[4] > kLeastCurveSpeed, v[5], v[9]);
        });
    for (std::uint32_t k = done; k < segment.sliceCount; ++k) addScalar(m, segment, k, halfDiagonal);
    return m;
}

double fastestCurveSpeed(const SegmentPoints& points, SliceLanes lanes) {
    constexpr std::uint32_t kSpeeds = 17;
    double p[4][3];
    for (int i = 0; i < 4; ++i)
        for (int a = 0; a < 3; ++a) p[i][a] = points[i][a];
    // The largest of them: exact, so in any order. The first 16 in lanes.
    double fastest = 0.0;
    std::uint32_t j = 0;
#if defined(__x86_64__) || defined(__i386__)
    if (lanes == SliceLanes::Avx || (lanes == SliceLanes::Auto && cpuHasAvx())) {
        fastest = lanes::fastestSpeedLanesAvx(p, 4);
        j = 16;
    }
#endif
#if defined(__SSE2__)
    if (lanes != SliceLanes::Scalar && j == 0) {
        fastest = lanes::fastestSpeedLanes<lanes::Sse2Lanes>(p, 8);
        j = 16;
    }
#endif
    for (; j < kSpeeds; ++j) fastest = std::max(fastest, glm::length(evalCatmullRomDerivative(points, j / 16.0)));
    return fastest;
}

void sliceAxes(const SegmentRecord& segment, std::uint32_t first, std::uint32_t count, SliceAxis* out,
               SliceLanes lanes) {
    const std::uint32_t end = first + count;
    // The reach's half-diagonal does not matter here.
    std::uint32_t k = measureInLanes(segment, 1.0, first, end, lanes, [&](std::uint32_t slice, const double* v) {
        out[slice - first] = {glm::dvec3(v[0], v[1], v[2]), glm::dvec3(v[6], v[7], v[8]), v[3]};
    });
    for (; k < end; ++k) {
        const SliceOnCurve g = sliceOnCurve(segment, k);
        out[k - first] = {g.center, g.tangent, g.thickness};
    }
}

void sliceVoxels(const SegmentRecord& segment, std::uint32_t first, std::uint32_t count, const glm::dvec3& origin,
                 double invVoxelSize, glm::ivec3* out, SliceLanes lanes) {
    const std::uint32_t end = first + count, slices = segment.sliceCount;
    const double from[3] = {origin.x, origin.y, origin.z};
    std::uint32_t k = inLanes<lanes::kSliceVoxelValues>(
        segment, first, end, lanes,
        [&](const double (&p)[4][3], std::uint32_t group, double (&values)[4][lanes::kSliceVoxelValues]) {
            lanes::sliceVoxelLanesAvx(p, slices, group, from, invVoxelSize, values);
        },
        [&](const double (&p)[4][3], std::uint32_t group, double (&values)[2][lanes::kSliceVoxelValues]) {
            lanes::sliceVoxelLanes<lanes::Sse2Lanes>(p, slices, group, from, invVoxelSize, values);
        },
        [&](std::uint32_t slice, const double* v) { out[slice - first] = glm::ivec3(glm::dvec3(v[0], v[1], v[2])); });
    // sliceOnCurve's centre, one slice at a time.
    const double invK = 1.0 / slices;
    for (; k < end; ++k)
        out[k - first] = voxelHolding(evalCatmullRom(segment.points, (k + 0.5) * invK), origin, invVoxelSize);
}

} // namespace yv

// A segment's slices measured a vector of lanes at a time: the operations of
// sliceOnCurve and evalCatmullRom* (garment/slices.cpp, catmull_rom.h) in the
// same order, each exactly rounded in every lane, so each lane gives the bits
// of one slice at a time. Private to slice_measures*.cpp: each includes it
// with its own lane type (core/double_lanes.h), compiled for its own
// instruction set, so it uses no glm (whose inline functions an -mavx file
// must not emit).
#pragma once

#include <cstdint>

namespace yv::lanes {

// The steps below are inlined into each kernel: called (a slice's four
// derivatives each a call), their lanes went through memory between them.
#define YV_LANES_INLINE [[gnu::always_inline]] inline

/// sum_i w[i] p[i] in C++'s order (((w0 p0 + w1 p1) + w2 p2) + w3 p3), times 0.5, per axis.
template <class L>
YV_LANES_INLINE void combineLanes(const double (&p)[4][3], const typename L::V (&w)[4], typename L::V (&v)[3]) {
    for (int a = 0; a < 3; ++a) {
        typename L::V s = L::add(L::mul(w[0], L::set1(p[0][a])), L::mul(w[1], L::set1(p[1][a])));
        s = L::add(s, L::mul(w[2], L::set1(p[2][a])));
        s = L::add(s, L::mul(w[3], L::set1(p[3][a])));
        v[a] = L::mul(L::set1(0.5), s);
    }
}

/// evalCatmullRom at t.
template <class L>
YV_LANES_INLINE void positionLanes(const double (&p)[4][3], typename L::V t, typename L::V (&v)[3]) {
    using V = typename L::V;
    const auto c = [](double x) { return L::set1(x); };
    const V t2 = L::mul(t, t), t3 = L::mul(t2, t);
    // -0.0 - x is -x exactly, as C++'s unary minus.
    const V w[4] = {L::sub(L::add(L::sub(c(-0.0), t), L::mul(c(2.0), t2)), t3),
                    L::add(L::sub(c(2.0), L::mul(c(5.0), t2)), L::mul(c(3.0), t3)),
                    L::sub(L::add(t, L::mul(c(4.0), t2)), L::mul(c(3.0), t3)), L::add(L::sub(c(-0.0), t2), t3)};
    combineLanes<L>(p, w, v);
}

/// evalCatmullRomDerivative at t.
template <class L>
YV_LANES_INLINE void derivativeLanes(const double (&p)[4][3], typename L::V t, typename L::V (&d)[3]) {
    using V = typename L::V;
    const auto c = [](double x) { return L::set1(x); };
    const V t2 = L::mul(t, t);
    const V w[4] = {L::sub(L::add(c(-1.0), L::mul(c(4.0), t)), L::mul(c(3.0), t2)),
                    L::add(L::mul(c(-10.0), t), L::mul(c(9.0), t2)),
                    L::sub(L::add(c(1.0), L::mul(c(8.0), t)), L::mul(c(9.0), t2)),
                    L::add(L::mul(c(-2.0), t), L::mul(c(3.0), t2))};
    combineLanes<L>(p, w, d);
}

/// glm::dot in its order, (x x' + y y') + z z'.
template <class L>
YV_LANES_INLINE typename L::V dotLanes(const typename L::V (&a)[3], const typename L::V (&b)[3]) {
    return L::add(L::add(L::mul(a[0], b[0]), L::mul(a[1], b[1])), L::mul(a[2], b[2]));
}

/// Slice indices first .. first + L::width - 1, as doubles.
template <class L>
typename L::V sliceIndexLanes(std::uint32_t first) {
    double index[L::width];
    for (int l = 0; l < L::width; ++l) index[l] = double(first + std::uint32_t(l));
    return L::load(index);
}

/// What measureSliceLanes gives of each slice: its centre (x, y, z), its
/// thickness, the curve's speed there, the reach its samples have, its unit
/// tangent (x, y, z) and that tangent's largest component (in absolute
/// value), the last three where the curve moves there (speed above
/// kLeastCurveSpeed; else they are meaningless).
constexpr int kSliceMeasureValues = 10;

/// Slices first .. first + L::width - 1 of a segment with control points `p`
/// and `count` slices, into out[lane][...]; `halfDiagonal`: the slice square's.
template <class L>
void measureSliceLanes(const double (&p)[4][3], std::uint32_t count, std::uint32_t first, double halfDiagonal,
                       double (&out)[L::width][kSliceMeasureValues]) {
    using V = typename L::V;
    const auto c = [](double x) { return L::set1(x); };
    const auto derivative = [&](V t, V (&d)[3]) { derivativeLanes<L>(p, t, d); };
    const auto dot = [](const V (&a)[3], const V (&b)[3]) { return dotLanes<L>(a, b); };
    const auto length = [&](const V (&a)[3]) { return L::sqrt(dot(a, a)); };

    const V k = sliceIndexLanes<L>(first);
    const V invK = c(1.0 / count);
    const V t = L::mul(L::add(k, c(0.5)), invK);

    V centre[3];
    positionLanes<L>(p, t, centre);
    V d1[3];
    derivative(t, d1);

    // catmullRomArcLength over [k / K, (k + 1) / K].
    V thickness;
    {
        const V t0 = L::mul(k, invK), t1 = L::mul(L::add(k, c(1.0)), invK);
        const V mid = L::mul(c(0.5), L::add(t0, t1)), half = L::mul(c(0.5), L::sub(t1, t0));
        const V node = L::mul(L::sqrt(c(0.6)), half); // sqrt is exactly rounded, as std::sqrt(0.6)
        V a[3], b[3], e[3];
        derivative(L::sub(mid, node), a);
        derivative(mid, b);
        derivative(L::add(mid, node), e);
        const V sum = L::add(L::add(L::mul(c(5.0 / 9.0), length(a)), L::mul(c(8.0 / 9.0), length(b))),
                             L::mul(c(5.0 / 9.0), length(e)));
        thickness = L::mul(half, sum);
    }

    const V speed = length(d1);
    V tangent[3];
    for (int a = 0; a < 3; ++a) tangent[a] = L::div(d1[a], speed);
    V d2[3];
    {
        const V w[4] = {L::sub(c(4.0), L::mul(c(6.0), t)), L::add(c(-10.0), L::mul(c(18.0), t)),
                        L::sub(c(8.0), L::mul(c(18.0), t)), L::add(c(-2.0), L::mul(c(6.0), t))};
        combineLanes<L>(p, w, d2);
    }
    V curvature[3];
    {
        const V along = dot(d2, tangent), squaredSpeed = dot(d1, d1);
        for (int a = 0; a < 3; ++a) curvature[a] = L::div(L::sub(d2[a], L::mul(along, tangent[a])), squaredSpeed);
    }
    // measureSegment: the slab's depth along its dominant axis, thicker on a bend's outer side.
    const V dominant = L::max(L::max(L::abs(tangent[0]), L::abs(tangent[1])), L::abs(tangent[2]));
    const V depth =
        L::div(L::mul(L::add(c(1.0), L::mul(length(curvature), c(halfDiagonal))), thickness), dominant);
    const V reach = L::add(c(halfDiagonal), L::mul(c(0.5), depth));

    double lanesOf[kSliceMeasureValues][L::width];
    L::store(lanesOf[0], centre[0]);
    L::store(lanesOf[1], centre[1]);
    L::store(lanesOf[2], centre[2]);
    L::store(lanesOf[3], thickness);
    L::store(lanesOf[4], speed);
    L::store(lanesOf[5], reach);
    for (int a = 0; a < 3; ++a) L::store(lanesOf[6 + a], tangent[a]);
    L::store(lanesOf[9], dominant);
    for (int l = 0; l < L::width; ++l)
        for (int v = 0; v < kSliceMeasureValues; ++v) out[l][v] = lanesOf[v][l];
}

/// The largest of the curve's speeds, |evalCatmullRomDerivative(t)| as
/// glm::length gives it, at t = j / 16 for j = 0 .. groups * L::width - 1:
/// what planSlices takes (with t = 1's) to choose a segment's slice count.
/// The groups in one body, so that their square roots overlap.
template <class L>
double fastestSpeedLanes(const double (&p)[4][3], std::uint32_t groups) {
    typename L::V fastest = L::set1(0.0);
    for (std::uint32_t g = 0; g < groups; ++g) {
        // j * (1 / 16) is j / 16 exactly: a power of two.
        const typename L::V t = L::mul(sliceIndexLanes<L>(g * L::width), L::set1(1.0 / 16.0));
        typename L::V d[3];
        derivativeLanes<L>(p, t, d);
        fastest = L::max(fastest, L::sqrt(dotLanes<L>(d, d))); // exact, so in any order
    }
    double lanes[L::width];
    L::store(lanes, fastest);
    double most = 0.0;
    for (double s : lanes) most = most < s ? s : most;
    return most;
}

/// What the zoom plan's heat takes from each slice: the voxel holding its
/// centre (x, y, z, floored).
constexpr int kSliceVoxelValues = 3;

/// Slices first .. first + L::width - 1 as the heat places them: the centre
/// sliceOnCurve gives (at t = (k + 0.5) * (1 / K)) and the voxel
/// floor((centre - origin) * invVoxelSize) holding it, into out[lane][...].
/// Only the curve's position: no division or square root but the one 1 / K.
template <class L>
void sliceVoxelLanes(const double (&p)[4][3], std::uint32_t count, std::uint32_t first, const double (&origin)[3],
                     double invVoxelSize, double (&out)[L::width][kSliceVoxelValues]) {
    const typename L::V t = L::mul(L::add(sliceIndexLanes<L>(first), L::set1(0.5)), L::set1(1.0 / count));
    typename L::V centre[3];
    positionLanes<L>(p, t, centre);
    double lanesOf[kSliceVoxelValues][L::width];
    for (int a = 0; a < 3; ++a)
        L::store(lanesOf[a], L::floor(L::mul(L::sub(centre[a], L::set1(origin[a])), L::set1(invVoxelSize))));
    for (int l = 0; l < L::width; ++l)
        for (int v = 0; v < kSliceVoxelValues; ++v) out[l][v] = lanesOf[v][l];
}

#undef YV_LANES_INLINE

} // namespace yv::lanes

#include "core/principal_axis_pair.h"

#include "core/bricks.h"

#include <glm/geometric.hpp>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace yv {

#if defined(__SSE2__)
namespace {

/// `yes` in the lanes of `mask`, `no` in the others.
inline __m128d select(__m128d mask, __m128d yes, __m128d no) {
    return _mm_or_pd(_mm_and_pd(mask, yes), _mm_andnot_pd(mask, no));
}

/// The rotation of principalAxis (cyclic Jacobi, the same operations in the
/// same order, each exactly rounded in either lane), applied in the lanes of
/// `rotate` only.
inline void rotate(__m128d (&a)[3][3], __m128d (&v)[3][3], int p, int q, __m128d rotate) {
    const __m128d one = _mm_set1_pd(1.0);
    const __m128d theta = _mm_div_pd(_mm_sub_pd(a[q][q], a[p][p]), _mm_mul_pd(_mm_set1_pd(2.0), a[p][q]));
    const __m128d sign = select(_mm_cmpge_pd(theta, _mm_setzero_pd()), one, _mm_set1_pd(-1.0));
    const __m128d magnitude = _mm_andnot_pd(_mm_set1_pd(-0.0), theta);
    const __m128d tt = _mm_div_pd(sign, _mm_add_pd(magnitude, _mm_sqrt_pd(_mm_add_pd(_mm_mul_pd(theta, theta), one))));
    const __m128d c = _mm_div_pd(one, _mm_sqrt_pd(_mm_add_pd(_mm_mul_pd(tt, tt), one))), s = _mm_mul_pd(tt, c);
    for (int k = 0; k < 3; ++k) { // A <- A J
        const __m128d akp = a[k][p], akq = a[k][q];
        a[k][p] = select(rotate, _mm_sub_pd(_mm_mul_pd(c, akp), _mm_mul_pd(s, akq)), akp);
        a[k][q] = select(rotate, _mm_add_pd(_mm_mul_pd(s, akp), _mm_mul_pd(c, akq)), akq);
    }
    for (int k = 0; k < 3; ++k) { // A <- J^T A
        const __m128d apk = a[p][k], aqk = a[q][k];
        a[p][k] = select(rotate, _mm_sub_pd(_mm_mul_pd(c, apk), _mm_mul_pd(s, aqk)), apk);
        a[q][k] = select(rotate, _mm_add_pd(_mm_mul_pd(s, apk), _mm_mul_pd(c, aqk)), aqk);
    }
    for (int k = 0; k < 3; ++k) { // V <- V J
        const __m128d vkp = v[k][p], vkq = v[k][q];
        v[k][p] = select(rotate, _mm_sub_pd(_mm_mul_pd(c, vkp), _mm_mul_pd(s, vkq)), vkp);
        v[k][q] = select(rotate, _mm_add_pd(_mm_mul_pd(s, vkp), _mm_mul_pd(c, vkq)), vkq);
    }
}

/// The eigenvector of the largest diagonal entry in lane `lane`, as principalAxis picks it.
glm::dvec3 largestAxis(const __m128d (&a)[3][3], const __m128d (&v)[3][3], int lane) {
    const auto at = [lane](__m128d x) {
        double both[2];
        _mm_storeu_pd(both, x);
        return both[lane];
    };
    int best = 0;
    for (int i = 1; i < 3; ++i)
        if (at(a[i][i]) > at(a[best][best])) best = i;
    return glm::normalize(glm::dvec3(at(v[0][best]), at(v[1][best]), at(v[2][best])));
}

} // namespace

void principalAxisPair(const double t0[6], const double t1[6], glm::dvec3& axis0, glm::dvec3& axis1) {
    const auto both = [&](int i) { return _mm_set_pd(t1[i], t0[i]); }; // lane 0: t0
    const __m128d zero = _mm_setzero_pd(), one = _mm_set1_pd(1.0);
    __m128d a[3][3] = {{both(0), both(3), both(4)}, {both(3), both(1), both(5)}, {both(4), both(5), both(2)}};
    __m128d v[3][3] = {{one, zero, zero}, {zero, one, zero}, {zero, zero, one}};
    __m128d live = _mm_cmpeq_pd(zero, zero); // lanes still sweeping
    for (int sweep = 0; sweep < 12; ++sweep) {
        const __m128d off = _mm_add_pd(_mm_add_pd(_mm_mul_pd(a[0][1], a[0][1]), _mm_mul_pd(a[0][2], a[0][2])),
                                       _mm_mul_pd(a[1][2], a[1][2]));
        const __m128d diag = _mm_add_pd(_mm_add_pd(_mm_mul_pd(a[0][0], a[0][0]), _mm_mul_pd(a[1][1], a[1][1])),
                                        _mm_mul_pd(a[2][2], a[2][2]));
        const __m128d converged =
            _mm_or_pd(_mm_cmple_pd(off, _mm_mul_pd(_mm_set1_pd(1e-30), diag)), _mm_cmpeq_pd(off, zero));
        live = _mm_andnot_pd(converged, live);
        if (_mm_movemask_pd(live) == 0) break;
        for (int p = 0; p < 2; ++p)
            for (int q = p + 1; q < 3; ++q) {
                const __m128d turn = _mm_andnot_pd(_mm_cmpeq_pd(a[p][q], zero), live);
                if (_mm_movemask_pd(turn) != 0) rotate(a, v, p, q, turn);
            }
    }
    axis0 = largestAxis(a, v, 0);
    axis1 = largestAxis(a, v, 1);
}

#else

void principalAxisPair(const double t0[6], const double t1[6], glm::dvec3& axis0, glm::dvec3& axis1) {
    axis0 = principalAxis(t0);
    axis1 = principalAxis(t1);
}

#endif

} // namespace yv

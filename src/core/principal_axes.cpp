#include "core/principal_axes.h"

#include "core/bricks.h"
#include "core/principal_axes_jacobi.h"

#include <glm/geometric.hpp>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace yv {

namespace {

#if defined(__SSE2__)
/// Two lanes in SSE2, which every x86-64 has.
struct Sse2Lanes {
    using V = __m128d;
    static constexpr int width = 2;
    static V set1(double x) { return _mm_set1_pd(x); }
    static V load(const double* x) { return _mm_loadu_pd(x); }
    static void store(double* x, V v) { _mm_storeu_pd(x, v); }
    static V add(V x, V y) { return _mm_add_pd(x, y); }
    static V sub(V x, V y) { return _mm_sub_pd(x, y); }
    static V mul(V x, V y) { return _mm_mul_pd(x, y); }
    static V div(V x, V y) { return _mm_div_pd(x, y); }
    static V sqrt(V x) { return _mm_sqrt_pd(x); }
    static V cmpge(V x, V y) { return _mm_cmpge_pd(x, y); }
    static V cmple(V x, V y) { return _mm_cmple_pd(x, y); }
    static V cmpeq(V x, V y) { return _mm_cmpeq_pd(x, y); }
    static V bitOr(V x, V y) { return _mm_or_pd(x, y); }
    static V andNot(V x, V y) { return _mm_andnot_pd(x, y); } ///< ~x & y
    static V select(V mask, V yes, V no) { return _mm_or_pd(_mm_and_pd(mask, yes), _mm_andnot_pd(mask, no)); }
    static bool none(V mask) { return _mm_movemask_pd(mask) == 0; }
};
#endif

glm::dvec3 normalized(const double (&axis)[3]) { return glm::normalize(glm::dvec3(axis[0], axis[1], axis[2])); }

/// The tensors' axes `width` at a time through `eigenvectors`, as many as
/// whole groups take; returns how many (the caller does the rest).
template <int width, class Eigenvectors>
int inGroups(const double (*tensors)[6], glm::dvec3* axes, int count, Eigenvectors&& eigenvectors) {
    int i = 0;
    for (; i + width <= count; i += width) {
        const double* group[width];
        for (int l = 0; l < width; ++l) group[l] = tensors[i + l];
        double found[width][3];
        eigenvectors(group, found);
        for (int l = 0; l < width; ++l) axes[i + l] = normalized(found[l]);
    }
    return i;
}

} // namespace

bool avxAxisLanesAvailable() {
#if defined(__x86_64__) || defined(__i386__)
    // GCC's check covers the operating system's saving of the AVX registers too.
    static const bool available = __builtin_cpu_supports("avx");
    return available;
#else
    return false;
#endif
}

void principalAxes(const double (*tensors)[6], glm::dvec3* axes, int count, AxisLanes lanes) {
    int done = 0;
#if defined(__x86_64__) || defined(__i386__)
    const bool avx = lanes == AxisLanes::Avx || (lanes == AxisLanes::Auto && avxAxisLanesAvailable());
    if (avx) done = inGroups<8>(tensors, axes, count, jacobi::largestEigenvectorsAvx);
#endif
#if defined(__SSE2__)
    done += inGroups<2>(tensors + done, axes + done, count - done, jacobi::largestEigenvectors<Sse2Lanes>);
#endif
    for (; done < count; ++done) axes[done] = principalAxis(tensors[done]);
}

} // namespace yv

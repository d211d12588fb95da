// Eight lanes of principalAxis in AVX. This file alone is built with -mavx
// and is called only where the CPU has AVX (avxAxisLanesAvailable). So that
// no inline function of a shared header is emitted here in AVX code (and
// picked by the linker for callers on any CPU), it includes only the Jacobi
// template and the intrinsics.
#include "core/principal_axes_jacobi.h"

#if defined(__AVX__)
#include <immintrin.h>

namespace yv::jacobi {

namespace {

struct AvxLanes {
    using V = __m256d;
    static constexpr int width = 4;
    static V set1(double x) { return _mm256_set1_pd(x); }
    static V load(const double* x) { return _mm256_loadu_pd(x); }
    static void store(double* x, V v) { _mm256_storeu_pd(x, v); }
    static V add(V x, V y) { return _mm256_add_pd(x, y); }
    static V sub(V x, V y) { return _mm256_sub_pd(x, y); }
    static V mul(V x, V y) { return _mm256_mul_pd(x, y); }
    static V div(V x, V y) { return _mm256_div_pd(x, y); }
    static V sqrt(V x) { return _mm256_sqrt_pd(x); }
    static V cmpge(V x, V y) { return _mm256_cmp_pd(x, y, _CMP_GE_OQ); }
    static V cmple(V x, V y) { return _mm256_cmp_pd(x, y, _CMP_LE_OQ); }
    static V cmpeq(V x, V y) { return _mm256_cmp_pd(x, y, _CMP_EQ_OQ); }
    static V bitOr(V x, V y) { return _mm256_or_pd(x, y); }
    static V andNot(V x, V y) { return _mm256_andnot_pd(x, y); } ///< ~x & y
    static V select(V mask, V yes, V no) { return _mm256_blendv_pd(no, yes, mask); }
    static bool none(V mask) { return _mm256_movemask_pd(mask) == 0; }
};

/// Eight lanes as two AVX vectors: a rotation is a chain of divisions and
/// square roots, each waiting on the last, and two independent chains keep
/// the divider busy where one leaves it idle most of the time.
struct AvxPairLanes {
    struct V {
        __m256d lo, hi;
    };
    static constexpr int width = 8;
    template <class Op>
    static V each(V x, V y, Op op) { return {op(x.lo, y.lo), op(x.hi, y.hi)}; }
    static V set1(double x) { return {_mm256_set1_pd(x), _mm256_set1_pd(x)}; }
    static V load(const double* x) { return {_mm256_loadu_pd(x), _mm256_loadu_pd(x + 4)}; }
    static void store(double* x, V v) { _mm256_storeu_pd(x, v.lo), _mm256_storeu_pd(x + 4, v.hi); }
    static V add(V x, V y) { return each(x, y, AvxLanes::add); }
    static V sub(V x, V y) { return each(x, y, AvxLanes::sub); }
    static V mul(V x, V y) { return each(x, y, AvxLanes::mul); }
    static V div(V x, V y) { return each(x, y, AvxLanes::div); }
    static V sqrt(V x) { return {_mm256_sqrt_pd(x.lo), _mm256_sqrt_pd(x.hi)}; }
    static V cmpge(V x, V y) { return each(x, y, AvxLanes::cmpge); }
    static V cmple(V x, V y) { return each(x, y, AvxLanes::cmple); }
    static V cmpeq(V x, V y) { return each(x, y, AvxLanes::cmpeq); }
    static V bitOr(V x, V y) { return each(x, y, AvxLanes::bitOr); }
    static V andNot(V x, V y) { return each(x, y, AvxLanes::andNot); } ///< ~x & y
    static V select(V mask, V yes, V no) { return {AvxLanes::select(mask.lo, yes.lo, no.lo), AvxLanes::select(mask.hi, yes.hi, no.hi)}; }
    static bool none(V mask) { return AvxLanes::none(_mm256_or_pd(mask.lo, mask.hi)); }
};

} // namespace

void largestEigenvectorsAvx(const double* const (&t)[8], double (&axes)[8][3]) { largestEigenvectors<AvxPairLanes>(t, axes); }

} // namespace yv::jacobi

#endif

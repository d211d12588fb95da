// Vectors of doubles for code written once for any width (the brick
// resolve's principal axes, the slices' measures): each operation the IEEE
// one, lane by lane, so each lane gives the scalar code's bits. Sse2Lanes
// (two lanes) wherever the compiler targets SSE2, as every x86-64 does;
// AvxLanes (four) and AvxPairLanes (eight, two independent chains side by
// side) only in the files built with -mavx, called where cpuHasAvx().
//
// In an anonymous namespace on purpose: the -mavx files include this too,
// and their copies of these inline functions must never be the ones the
// linker keeps for callers on a CPU without AVX.
#pragma once

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__AVX__)
#include <immintrin.h>
#endif

namespace yv::lanes {

namespace {

#if defined(__SSE2__)
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
    static V max(V x, V y) { return _mm_max_pd(x, y); }
    static V abs(V x) { return _mm_andnot_pd(_mm_set1_pd(-0.0), x); }
    /// std::floor for |x| < 2^31 (SSE2 has no rounding instruction): the
    /// truncation, one less where that rounded up.
    static V floor(V x) {
        const V truncated = _mm_cvtepi32_pd(_mm_cvttpd_epi32(x));
        return _mm_sub_pd(truncated, _mm_and_pd(_mm_cmplt_pd(x, truncated), _mm_set1_pd(1.0)));
    }
    static V cmpge(V x, V y) { return _mm_cmpge_pd(x, y); }
    static V cmple(V x, V y) { return _mm_cmple_pd(x, y); }
    static V cmpeq(V x, V y) { return _mm_cmpeq_pd(x, y); }
    static V bitOr(V x, V y) { return _mm_or_pd(x, y); }
    static V andNot(V x, V y) { return _mm_andnot_pd(x, y); } ///< ~x & y
    static V select(V mask, V yes, V no) { return _mm_or_pd(_mm_and_pd(mask, yes), _mm_andnot_pd(mask, no)); }
    static bool none(V mask) { return _mm_movemask_pd(mask) == 0; }
};
#endif

#if defined(__AVX__)
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
    static V max(V x, V y) { return _mm256_max_pd(x, y); }
    static V abs(V x) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), x); }
    static V floor(V x) { return _mm256_floor_pd(x); }
    static V cmpge(V x, V y) { return _mm256_cmp_pd(x, y, _CMP_GE_OQ); }
    static V cmple(V x, V y) { return _mm256_cmp_pd(x, y, _CMP_LE_OQ); }
    static V cmpeq(V x, V y) { return _mm256_cmp_pd(x, y, _CMP_EQ_OQ); }
    static V bitOr(V x, V y) { return _mm256_or_pd(x, y); }
    static V andNot(V x, V y) { return _mm256_andnot_pd(x, y); } ///< ~x & y
    static V select(V mask, V yes, V no) { return _mm256_blendv_pd(no, yes, mask); }
    static bool none(V mask) { return _mm256_movemask_pd(mask) == 0; }
};

/// Eight lanes as two AVX vectors: where a computation is a chain of
/// divisions and square roots, each waiting on the last, two independent
/// chains keep the divider busy where one leaves it idle most of the time.
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
    static V max(V x, V y) { return each(x, y, AvxLanes::max); }
    static V abs(V x) { return {AvxLanes::abs(x.lo), AvxLanes::abs(x.hi)}; }
    static V cmpge(V x, V y) { return each(x, y, AvxLanes::cmpge); }
    static V cmple(V x, V y) { return each(x, y, AvxLanes::cmple); }
    static V cmpeq(V x, V y) { return each(x, y, AvxLanes::cmpeq); }
    static V bitOr(V x, V y) { return each(x, y, AvxLanes::bitOr); }
    static V andNot(V x, V y) { return each(x, y, AvxLanes::andNot); } ///< ~x & y
    static V select(V mask, V yes, V no) { return {AvxLanes::select(mask.lo, yes.lo, no.lo), AvxLanes::select(mask.hi, yes.hi, no.hi)}; }
    static bool none(V mask) { return AvxLanes::none(_mm256_or_pd(mask.lo, mask.hi)); }
};
#endif

} // namespace

} // namespace yv::lanes

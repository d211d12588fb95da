#include "core/half_floats.h"

#include "core/cpu_features.h"

#include <openvdb/Types.h>

#include <cstring>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define YV_HAVE_F16C_LANES 1
#endif

namespace yv {

#if defined(YV_HAVE_F16C_LANES)
namespace {

// The F16C lanes, compiled for AVX and F16C by their target attribute alone
// (no file-wide flag: no shared inline function is emitted in F16C code) and
// called only where cpuHasF16c(). Round to nearest even: Imath's rounding.
constexpr int kRound = _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC;

__attribute__((target("avx,f16c"))) void floatsToHalvesF16c(const float* in, unsigned char* out, std::size_t n) {
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8)
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 2 * i), _mm256_cvtps_ph(_mm256_loadu_ps(in + i), kRound));
    if (i < n) {
        float tail[8] = {};
        std::memcpy(tail, in + i, (n - i) * sizeof(float));
        alignas(16) std::uint16_t halves[8];
        _mm_store_si128(reinterpret_cast<__m128i*>(halves), _mm256_cvtps_ph(_mm256_loadu_ps(tail), kRound));
        std::memcpy(out + 2 * i, halves, 2 * (n - i));
    }
}

__attribute__((target("avx,f16c"))) void roundThroughHalvesF16c(const float* in, float* out, std::size_t n) {
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8)
        _mm256_storeu_ps(out + i, _mm256_cvtph_ps(_mm256_cvtps_ph(_mm256_loadu_ps(in + i), kRound)));
    if (i < n) {
        float tail[8] = {};
        std::memcpy(tail, in + i, (n - i) * sizeof(float));
        alignas(32) float rounded[8];
        _mm256_store_ps(rounded, _mm256_cvtph_ps(_mm256_cvtps_ph(_mm256_loadu_ps(tail), kRound)));
        std::memcpy(out + i, rounded, (n - i) * sizeof(float));
    }
}

} // namespace
#endif

void floatsToHalves(const float* in, void* out, std::size_t n) {
    auto* bytes = static_cast<unsigned char*>(out);
#if defined(YV_HAVE_F16C_LANES)
    if (cpuHasF16c()) return floatsToHalvesF16c(in, bytes, n);
#endif
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint16_t bits = openvdb::math::half(in[i]).bits();
        std::memcpy(bytes + 2 * i, &bits, 2);
    }
}

void roundThroughHalves(const float* in, float* out, std::size_t n) {
#if defined(YV_HAVE_F16C_LANES)
    if (cpuHasF16c()) return roundThroughHalvesF16c(in, out, n);
#endif
    for (std::size_t i = 0; i < n; ++i) out[i] = float(openvdb::math::half(in[i]));
}

} // namespace yv

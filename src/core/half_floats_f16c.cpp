// The F16C lanes of core/half_floats.h. This file is built with -mavx -mf16c
// and is called only where the CPU has F16C (cpuHasF16c); it includes no
// shared header with inline functions, so none is emitted here in F16C code.
#include <cstddef>
#include <cstdint>

#if defined(__F16C__)
#include <immintrin.h>

namespace yv::f16c {

// Round to nearest even: what Imath's float-to-half does.
constexpr int kRound = _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC;

void floatsToHalves(const float* in, void* out, std::size_t n) {
    auto* bytes = static_cast<unsigned char*>(out);
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8)
        _mm_storeu_si128(reinterpret_cast<__m128i*>(bytes + 2 * i), _mm256_cvtps_ph(_mm256_loadu_ps(in + i), kRound));
    if (i < n) {
        float tail[8] = {};
        for (std::size_t k = 0; i + k < n; ++k) tail[k] = in[i + k];
        alignas(16) std::uint16_t halves[8];
        _mm_store_si128(reinterpret_cast<__m128i*>(halves), _mm256_cvtps_ph(_mm256_loadu_ps(tail), kRound));
        for (std::size_t k = 0; i + k < n; ++k) __builtin_memcpy(bytes + 2 * (i + k), &halves[k], 2);
    }
}

void roundThroughHalves(const float* in, float* out, std::size_t n) {
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8)
        _mm256_storeu_ps(out + i, _mm256_cvtph_ps(_mm256_cvtps_ph(_mm256_loadu_ps(in + i), kRound)));
    if (i < n) {
        float tail[8] = {};
        for (std::size_t k = 0; i + k < n; ++k) tail[k] = in[i + k];
        alignas(32) float rounded[8];
        _mm256_store_ps(rounded, _mm256_cvtph_ps(_mm256_cvtps_ph(_mm256_loadu_ps(tail), kRound)));
        for (std::size_t k = 0; i + k < n; ++k) out[i + k] = rounded[k];
    }
}

} // namespace yv::f16c

#endif

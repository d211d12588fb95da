#include "core/half_floats.h"

#include <openvdb/Types.h>

#include <cstring>

namespace yv {

#if defined(__x86_64__) || defined(__i386__)
namespace f16c {
void floatsToHalves(const float* in, void* out, std::size_t n);
void roundThroughHalves(const float* in, float* out, std::size_t n);
} // namespace f16c
#endif

bool cpuHasF16c() {
#if defined(__x86_64__) || defined(__i386__)
    // The 256-bit forms need AVX's registers saved by the operating system too.
    static const bool available = __builtin_cpu_supports("avx") && __builtin_cpu_supports("f16c");
    return available;
#else
    return false;
#endif
}

void floatsToHalves(const float* in, void* out, std::size_t n) {
#if defined(__x86_64__) || defined(__i386__)
    if (cpuHasF16c()) return f16c::floatsToHalves(in, out, n);
#endif
    auto* bytes = static_cast<unsigned char*>(out);
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint16_t bits = openvdb::math::half(in[i]).bits();
        std::memcpy(bytes + 2 * i, &bits, 2);
    }
}

void roundThroughHalves(const float* in, float* out, std::size_t n) {
#if defined(__x86_64__) || defined(__i386__)
    if (cpuHasF16c()) return f16c::roundThroughHalves(in, out, n);
#endif
    for (std::size_t i = 0; i < n; ++i) out[i] = float(openvdb::math::half(in[i]));
}

} // namespace yv

#include "core/cpu_features.h"

#if defined(__x86_64__) || defined(__i386__)
#include <cpuid.h>
#endif

namespace yv {

bool cpuHasAvx() {
#if defined(__x86_64__) || defined(__i386__)
    // GCC's check covers the operating system's saving of the AVX registers too.
    static const bool available = __builtin_cpu_supports("avx");
    return available;
#else
    return false;
#endif
}

bool cpuHasF16c() {
#if defined(__x86_64__) || defined(__i386__)
    // Its 256-bit forms need AVX's registers (cpuHasAvx). Clang's
    // __builtin_cpu_supports knows no "f16c": CPUID leaf 1 says it.
    static const bool available = cpuHasAvx() && [] {
        unsigned a = 0, b = 0, c = 0, d = 0;
        return __get_cpuid(1, &a, &b, &c, &d) && (c & bit_F16C) != 0;
    }();
    return available;
#else
    return false;
#endif
}

} // namespace yv

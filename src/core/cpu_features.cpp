#include "core/cpu_features.h"

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

} // namespace yv

// What the CPU running yarnvox offers beyond the instruction set it was
// built for: the files built with -mavx, and the functions built for F16C by
// their target attribute, are called only where it has them.
#pragma once

namespace yv {

/// Whether this CPU and its operating system run AVX code.
bool cpuHasAvx();
/// Whether they run F16C's conversions between floats and halves (AVX's too).
bool cpuHasF16c();

} // namespace yv

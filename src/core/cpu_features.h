// What the CPU running yarnvox offers beyond the instruction set it was
// built for: the files built with -mavx are called only where it has AVX.
#pragma once

namespace yv {

/// Whether this CPU and its operating system run AVX code.
bool cpuHasAvx();

} // namespace yv

// Eight lanes of principalAxis in AVX. This file is built with -mavx and is
// called only where the CPU has AVX (cpuHasAvx). So that no
// inline function of a shared header is emitted here in AVX code (and picked
// by the linker for callers on any CPU), it includes only the Jacobi
// template and the lanes (core/double_lanes.h, internal to each file).
#include "core/principal_axes_jacobi.h"

#if defined(__AVX__)
#include "core/double_lanes.h"

namespace yv::jacobi {

void largestEigenvectorsAvx(const double* const (&t)[8], double (&axes)[8][3]) { largestEigenvectors<lanes::AvxPairLanes>(t, axes); }

} // namespace yv::jacobi

#endif

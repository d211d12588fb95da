// principalAxis for many tensors at once, the same bits as one after the
// other: resolving a brick spends most of its time in the Jacobi rotations'
// chain of divisions and square roots, and independent chains side by side
// in a vector register's lanes take about the time of one (two in SSE2's,
// four in AVX's, and two AVX chains side by side).
#pragma once

#include <glm/vec3.hpp>

namespace yv {

/// Which lanes principalAxes may use: Auto picks AVX (eight tensors at a
/// time) where the CPU and the operating system allow it, else SSE2 (two at
/// a time); tests force each path.
enum class AxisLanes { Auto, Sse2, Avx };

/// axes[i] = principalAxis(tensors[i]) for i < count, bit for bit (xx yy zz xy xz yz each).
void principalAxes(const double (*tensors)[6], glm::dvec3* axes, int count, AxisLanes lanes = AxisLanes::Auto);

} // namespace yv

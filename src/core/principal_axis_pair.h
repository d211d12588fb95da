// principalAxis for two tensors at once, the same bits as one after the other:
// resolving a brick spends most of its time in the Jacobi rotations' chain of
// divisions and square roots, and two independent chains side by side in
// SSE2's two lanes take about the time of one.
#pragma once

#include <glm/vec3.hpp>

namespace yv {

/// principalAxis(t0) and principalAxis(t1), bit for bit (xx yy zz xy xz yz each).
void principalAxisPair(const double t0[6], const double t1[6], glm::dvec3& axis0, glm::dvec3& axis1);

} // namespace yv

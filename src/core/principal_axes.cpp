#include "core/principal_axes.h"

#include "core/bricks.h"
#include "core/cpu_features.h"
#include "core/double_lanes.h"
#include "core/principal_axes_jacobi.h"

#include <glm/geometric.hpp>

namespace yv {

namespace {

glm::dvec3 normalized(const double (&axis)[3]) { return glm::normalize(glm::dvec3(axis[0], axis[1], axis[2])); }

/// The tensors' axes `width` at a time through `eigenvectors`, as many as
/// whole groups take; returns how many (the caller does the rest).
template <int width, class Eigenvectors>
int inGroups(const double (*tensors)[6], glm::dvec3* axes, int count, Eigenvectors&& eigenvectors) {
    int i = 0;
    for (; i + width <= count; i += width) {
        const double* group[width];
        for (int l = 0; l < width; ++l) group[l] = tensors[i + l];
        double found[width][3];
        eigenvectors(group, found);
        for (int l = 0; l < width; ++l) axes[i + l] = normalized(found[l]);
    }
    return i;
}

} // namespace

void principalAxes(const double (*tensors)[6], glm::dvec3* axes, int count, AxisLanes lanes) {
    int done = 0;
#if defined(__x86_64__) || defined(__i386__)
    const bool avx = lanes == AxisLanes::Avx || (lanes == AxisLanes::Auto && cpuHasAvx());
    if (avx) done = inGroups<8>(tensors, axes, count, jacobi::largestEigenvectorsAvx);
#endif
#if defined(__SSE2__)
    done += inGroups<2>(tensors + done, axes + done, count - done, jacobi::largestEigenvectors<lanes::Sse2Lanes>);
#endif
    for (; done < count; ++done) axes[done] = principalAxis(tensors[done]);
}

} // namespace yv

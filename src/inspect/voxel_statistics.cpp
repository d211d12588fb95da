#include "inspect/voxel_statistics.h"

#include "core/bricks.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace yv {

void VoxelStatistics::add(float density, glm::vec3 axis) {
    ++activeVoxels;
    const double d = density;
    densitySum += d;
    densityMax = std::max(densityMax, d);
    const int bin = d > 1.0 ? kBins - 1 : std::clamp(int(std::ceil(d * 10.0)) - 1, 0, kBins - 2);
    ++histogram[std::size_t(bin)];
    if (d > 1.0 + kOverOneMargin) ++aboveOne;
    const double length = glm::length(glm::dvec3(axis));
    if (std::abs(length - 1.0) < 1e-3) {
        ++unitAxes;
        axisComponentSum += glm::abs(glm::dvec3(axis));
    }
}

VoxelStatistics& VoxelStatistics::operator+=(const VoxelStatistics& o) {
    for (int i = 0; i < kBins; ++i) histogram[std::size_t(i)] += o.histogram[std::size_t(i)];
    activeVoxels += o.activeVoxels;
    aboveOne += o.aboveOne;
    densitySum += o.densitySum;
    densityMax = std::max(densityMax, o.densityMax);
    unitAxes += o.unitAxes;
    axisComponentSum += o.axisComponentSum;
    return *this;
}

} // namespace yv

#include "inspect/voxel_statistics.h"

#include "core/bricks.h"

#include <algorithm>
#include <cmath>

namespace yv {

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

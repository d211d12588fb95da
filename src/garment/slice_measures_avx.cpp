// Four slices at a time in AVX (garment/slice_lanes.h): their measures and the voxels holding their centres. This file is built
// with -mavx and called only where the CPU has AVX (cpuHasAvx). So that no
// inline function of a shared header is emitted here in AVX code (and picked
// by the linker for callers on any CPU), it includes only the lanes
// template and core/double_lanes.h (internal to each file).
#include "garment/slice_lanes.h"

#if defined(__AVX__)
#include "core/double_lanes.h"

namespace yv::lanes {

void measureSliceLanesAvx(const double (&p)[4][3], std::uint32_t count, std::uint32_t first, double halfDiagonal,
                          double (&out)[4][kSliceMeasureValues]) {
    measureSliceLanes<AvxLanes>(p, count, first, halfDiagonal, out);
}

void measureSliceLanesAvxPair(const double (&p)[4][3], std::uint32_t count, std::uint32_t first, double halfDiagonal,
                              double (&out)[8][kSliceMeasureValues]) {
    measureSliceLanes<AvxPairLanes>(p, count, first, halfDiagonal, out);
}

void sliceVoxelLanesAvx(const double (&p)[4][3], std::uint32_t count, std::uint32_t first, const double (&origin)[3],
                        double invVoxelSize, double (&out)[4][kSliceVoxelValues]) {
    sliceVoxelLanes<AvxLanes>(p, count, first, origin, invVoxelSize, out);
}

double fastestSpeedLanesAvx(const double (&p)[4][3], std::uint32_t groups) {
    return fastestSpeedLanes<AvxLanes>(p, groups);
}

} // namespace yv::lanes

#endif

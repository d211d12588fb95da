#include "gpu/gpu_layout.h"

#include <tbb/parallel_for.h>

#include <cstring>

namespace yv {

GpuSegments packSegments(const SlicePlan& plan, const VoxelGrid& grid) {
    GpuSegments gpu(plan.segments.size());
    packSegments(plan, grid, gpu.data());
    return gpu;
}

void packSegments(const SlicePlan& plan, const VoxelGrid& grid, GpuSegment* out) {
    const double invH = 1.0 / grid.voxelSize;
    tbb::parallel_for(std::size_t(0), plan.segments.size(), [&](std::size_t i) {
        const SegmentRecord& s = plan.segments[i];
        // Made here and stored whole: `out` may be write-combined memory.
        GpuSegment g;
        const glm::dvec3 anchor = glm::floor((s.points[1] - grid.origin) * invH);
        for (int j = 0; j < 4; ++j) {
            const glm::dvec3 p = (s.points[j] - grid.origin) * invH - anchor;
            g.p[j][0] = float(p.x), g.p[j][1] = float(p.y), g.p[j][2] = float(p.z);
        }
        g.p[0][3] = float(s.twistRate * grid.voxelSize);
        g.p[1][3] = float(anchor.x), g.p[2][3] = float(anchor.y), g.p[3][3] = float(anchor.z);
        g.up[0] = float(s.knotUp.x), g.up[1] = float(s.knotUp.y), g.up[2] = float(s.knotUp.z);
        g.up[3] = float(s.phaseStart);
        const float length = float(s.length * invH);
        g.info[0] = static_cast<std::uint32_t>(s.firstSlice);
        g.info[1] = s.sliceCount;
        std::memcpy(&g.info[2], &length, 4);
        g.info[3] = s.yarn;
        out[i] = g;
    });
}

} // namespace yv

// The paper's dense method, kept as a baseline for benchmarks: slices are
// rasterised with a fragment shader that imageStores into three dense GL_R8
// 3D textures (density, theta, phi; one byte each, as the paper), which are
// then read back and turned into the same sparse bricks the other backends
// produce. It only runs when the whole grid fits one 3D texture.
#pragma once

#include "core/bricks.h"
#include "core/stats.h"
#include "garment/cross_section.h"
#include "gpu/egl_context.h"
#include "garment/slices.h"
#include "gpu/gl_voxelizer.h"
#include "plan/grid.h"

#include <cstdint>
#include <string>

namespace yv {

struct DenseVoxelizeCounters {
    std::string renderer, platform;
    std::uint64_t textureBytes = 0; ///< GPU bytes of the three 3D textures (3 * voxel count)
    std::uint64_t instances = 0;    ///< slices drawn
    double clearSeconds = 0.0;      ///< clearing the textures (GPU drained at both ends)
    double rasterSeconds = 0.0;     ///< the one instanced draw (likewise)
    double readbackSeconds = 0.0;   ///< wall time of reading back and converting to bricks
};

/// The counters under --stats' names: renderer, platform, method ("dense"),
/// gpu_peak_bytes, slices_drawn, gpu_clear_seconds, gpu_raster_seconds,
/// readback_seconds.
JsonObject toJson(const DenseVoxelizeCounters& counters);

/// Voxelizes on `context` (made current on this thread) with the paper's
/// dense method: max density per voxel (always, whatever
/// settings.base.reduce says; the method has no other reduction) and the
/// orientation stored as two 8-bit angles. Same sampling rule as voxelizeGl,
/// so the result is comparable with voxelizeGl in Reduce::Max mode up to the
/// method's racy writes and 8-bit angles. Throws yv::Error when the grid
/// exceeds one 3D texture (the message starts "dense method: grid WxHxD
/// exceeds one 3D texture").
BrickVolume voxelizeDense(const SlicePlan& plan, const CrossSection& xs, const VoxelGrid& grid,
                          const GlVoxelizeSettings& settings, const GlContext& context,
                          DenseVoxelizeCounters* counters = nullptr);

} // namespace yv

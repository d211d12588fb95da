// The identity of a voxelize run, so --resume only trusts regions of the same run.
#pragma once

#include "garment/cross_section.h"
#include "garment/slices.h"
#include "plan/grid.h"
#include "plan/zoom_plan.h"
#include "vdb/vdb_writer.h"

#include <cstdint>
#include <optional>
#include <string>

namespace yv {

/// Hash of the code that samples the yarns: the text of every embedded shader
/// (YV_SHADER_NAMES, from CMake's YV_SHADERS) and kCpuSamplingRuleVersion.
std::uint64_t samplingCodeHash();

/// Hash of everything that decides the bricks: the yarnvox version
/// (YV_VERSION), the sampling code (samplingCodeHash), the garment file's bytes, the
/// slice options, the cross-section texture (and its albedo), the grid, the reduction, the overlap rule and
/// supersampling, the zoom regions (ids and bounds), the backend ("gl", "cpu"),
/// and a --bbox run's box (whole runs hash as they always have).
std::uint64_t runFingerprint(const std::string& inputPath, const SliceOptions& slices, const CrossSection& xs,
                             const VoxelGrid& grid, Reduce reduce, Overlap overlap, int supersample,
                             const ZoomPlan& zoom, const std::string& backend,
                             const std::optional<VoxelBox>& box = std::nullopt);

} // namespace yv

// What every backend is told about how samples become voxels (the sampling
// rule's choices, formats/sampling-rule.md), whichever backend runs.
#pragma once

#include "core/error.h"
#include "core/sampling.h"
#include "core/voxel_box.h"

#include <optional>
#include <string>

namespace yv {

/// Samples per voxel face along each axis: 1 to this.
constexpr int kMaxSupersample = 16;

/// How a backend reduces samples into voxels.
struct VoxelizeSettings {
    Reduce reduce = Reduce::Mean;
    int supersample = 1; ///< samples per voxel face along each axis
    bool quiet = true;   ///< no progress output
    Overlap overlap = Overlap::Clamp; ///< mean: clamp interpenetrating yarns' sum at 1, or keep it
    /// --bbox: samples land only in these voxels, so a run of a box leaves
    /// nothing outside it even where its zoom regions (whole bricks) reach
    /// past it; none: every voxel of the grid.
    std::optional<VoxelBox> clip;
};

/// Throws yv::Error unless 1 <= supersample <= kMaxSupersample: the one
/// statement of the rule, for the command line and every backend's entry.
inline void checkSupersample(int supersample) {
    if (supersample < 1 || supersample > kMaxSupersample)
        throw Error("--supersample must be 1 to " + std::to_string(kMaxSupersample) + " (got " +
                    std::to_string(supersample) + ")");
}

} // namespace yv

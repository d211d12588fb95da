// What every backend is told about how samples become voxels (the sampling
// rule's choices, formats/sampling-rule.md), whichever backend runs.
#pragma once

#include "core/sampling.h"

namespace yv {

/// How a backend reduces samples into voxels.
struct VoxelizeSettings {
    Reduce reduce = Reduce::Mean;
    int supersample = 1; ///< samples per voxel face along each axis
    bool quiet = true;   ///< no progress output
    Overlap overlap = Overlap::Clamp; ///< mean: clamp interpenetrating yarns' sum at 1, or keep it
};

} // namespace yv

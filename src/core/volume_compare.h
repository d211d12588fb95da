// Agreement between two volumes on the same grid (GL against the CPU reference).
#pragma once

#include "core/bricks.h"

#include <cstdint>

namespace yv {

struct VolumeComparison {
    double iou = 0.0;          ///< active voxels: |A and B| / |A or B|
    double massRatio = 0.0;    ///< mass(B) / mass(A)
    double meanAngleDeg = 0.0; ///< axis angle over voxels active in both, weighted by A's density
    std::uint64_t both = 0, onlyA = 0, onlyB = 0;
};

/// Compares B against reference A voxel by voxel.
VolumeComparison compareVolumes(const BrickVolume& a, const BrickVolume& b);

} // namespace yv

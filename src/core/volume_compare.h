// Agreement between two volumes on the same grid (GL against the CPU reference).
#pragma once

#include "core/bricks.h"

#include <cstdint>

namespace yv {

struct VolumeComparison {
    double iou = 0.0;          ///< active voxels: |A and B| / |A or B|
    double massRatio = 0.0;    ///< mass(B) / mass(A)
    double meanAngleDeg = 0.0; ///< axis angle over voxels active in both, weighted by A's density
    double maxDensityDiff = 0.0, meanDensityDiff = 0.0; ///< |density B - density A| over voxels active in both
    std::uint64_t densityWithin = 0; ///< voxels active in both whose densities differ by at most the tolerance
    std::uint64_t both = 0, onlyA = 0, onlyB = 0;

    /// Share of the voxels active in both whose densities agree within the tolerance.
    double densityWithinShare() const { return both ? double(densityWithin) / double(both) : 1.0; }
};

/// Compares B against reference A voxel by voxel; densities agree when they
/// differ by at most `densityTolerance`.
VolumeComparison compareVolumes(const BrickVolume& a, const BrickVolume& b, double densityTolerance = 1e-4);

} // namespace yv

// Checks, before any slicing, that a run can leave its yarns in the volume:
// a yarn far thinner than a voxel rounds to nothing in the fixed-point sums,
// and a textured cross-section finer than a sample pixel is missed.
#pragma once

#include "garment/cross_section.h"

#include <string>
#include <vector>

namespace yv {

struct RunScale {
    double radius = 0.0;         ///< yarn radius, world units
    std::string radiusSource;    ///< where it came from, for messages ("--yarn-radius 0.1")
    double voxelSize = 0.0;      ///< world units
    std::string voxelSource;     ///< "--resolution 64" or "--voxel-size 0.1"
    int supersample = 1;
    double sliceSpacing = 0.0;   ///< explicit --slice-spacing, 0 when none
};

/// Throws yv::Error when the yarns would leave no voxel (the cross-section's
/// fibre area under 64 fixed-point units of a voxel face, or a textured cross-
/// section narrower than a quarter of a sample pixel) or when --slice-spacing
/// asks for more than 64 slices per voxel. Returns warnings (one line each,
/// without "warning: ") where the run works but the result is coarse.
std::vector<std::string> checkRunScale(const RunScale& scale, const CrossSection& xs);

} // namespace yv

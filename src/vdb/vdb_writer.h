// OpenVDB output: a float grid "density" (fog volume, background 0) and a
// vec3 grid "orientation" sharing one transform, built leaf by leaf.
#pragma once

#include "core/bricks.h"

#include <cstdint>
#include <string>

namespace yv {

struct VolumeMetadata {
    std::string input;        ///< garment file or generator description
    std::string backend;      ///< "cpu" or "gl"
    std::string crossSection; ///< "fibers", "disk" or a PNG path
    int resolution = 0;       ///< voxels on the longest axis asked for (0: from voxel size)
    std::uint64_t sliceCount = 0;
    double yarnRadius = 0.0;
    double twist = 0.0;
    int supersample = 1;
};

/// Writes `volume` to `path` through a temporary file and a rename, so a
/// failed run never leaves a file that looks finished. Voxel (i, j, k) of the
/// grid has index (i, j, k) and its centre at grid.origin + (i + 0.5) h.
void writeVdb(const std::string& path, const BrickVolume& volume, const VolumeMetadata& metadata);

} // namespace yv

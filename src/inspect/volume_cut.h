// `--render cut`: one axis-aligned plane of voxels at full resolution, one
// pixel per voxel, whatever the GPU budget: only the bricks the plane
// crosses are read, on the host.
#pragma once

#include "inspect/png_image.h"
#include "inspect/volume_source.h"

#include <string>

namespace yv {

struct CutPlane {
    int axis = 2; ///< 0 x, 1 y, 2 z
    int index = 0; ///< voxel index along that axis
};

/// Parses "x|y|z:INDEX"; throws yv::Error saying what is wrong.
CutPlane parseCut(const std::string& text);

/// The plane through `box` as an image: grey level round(255 * density),
/// densities clamped to [0, 1]. Cut z: x to the right, y up; cut y: x to the
/// right, z up; cut x: y to the right, z up. Throws yv::Error when the index
/// lies outside `box`.
RgbImage renderCut(const VolumeSource& source, const VoxelBox& box, const CutPlane& cut);

} // namespace yv

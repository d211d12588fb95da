// `inspect --render ... --regions`: the zoom regions' boxes drawn over a
// picture, each in the colour of its heat on a ramp from blue (the coolest
// region) through red to yellow (the hottest), with the ramp as a legend bar
// along the picture's bottom left.
#pragma once

#include "inspect/camera.h"
#include "inspect/png_image.h"
#include "inspect/volume_source.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace yv {

struct RegionHeat {
    std::uint64_t id = 0;
    VoxelBox box;
    double heat = 0.0; ///< what the colour says (active voxels: the store keeps no fragment counts)
};

/// The colour of `t` in [0, 1] on the heat ramp (blue, red, yellow), 0 to 1 each.
glm::vec3 heatColour(double t);

/// Draws the twelve edges of every region's box as seen by `camera` over
/// `image` (clipped at the near plane and the picture's border), coloured by
/// heat between the smallest and the largest, then the legend bar.
void drawRegionOutlines(RgbImage& image, const Camera& camera, const std::vector<RegionHeat>& regions);

} // namespace yv

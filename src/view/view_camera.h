// The camera of a live view: inspect's framing of a voxel box (azimuth,
// elevation, distance in bounding-sphere radii, inspect/camera.h) with the
// point looked at panned across the picture, so orbit, pan and zoom from the
// page map onto the cameras every renderer already takes.
#pragma once

#include "inspect/camera.h"
#include "view/view_message.h"

namespace yv {

/// The perspective camera of `view` around `box`, `width` x `height` pixels.
/// Without pan it is frameBox's camera; a pan of 1 moves the point looked at
/// one sphere radius along the picture's right (panX) or up (panY).
Camera viewCamera(const VoxelBox& box, const ViewCamera& view, int width, int height);

/// The radius of `box`'s bounding sphere, the unit of a view's distance and pan.
double viewRadius(const VoxelBox& box);

/// The same camera in coordinates p' = scale * p + offset (scale > 0): the
/// same picture of a volume whose voxels are `scale` times finer.
Camera mapCamera(const Camera& camera, double scale, const glm::dvec3& offset);

/// The same camera with its near and far planes around `box`'s bounding
/// sphere, as frameBox's are around its own: a volume mapped from a finer
/// one (scale < 1) reaches past the planes that framed the finer one, and
/// the ray caster's box faces would be cut off there.
Camera enclosing(const Camera& camera, const VoxelBox& box);

} // namespace yv

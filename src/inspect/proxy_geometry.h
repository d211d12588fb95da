// The proxy geometry of object-order empty-space skipping: the boundary of
// the union of occupied bricks, as triangles. Rasterised before the march,
// it gives each pixel's nearest entry into and farthest exit from occupied
// space (../shared/reference/empty-space-skipping-opengl4.txt).
#pragma once

#include "inspect/brick_level.h"

#include <glm/vec3.hpp>

#include <vector>

namespace yv {

/// Two triangles for every face of an occupied level brick whose neighbour
/// across it is empty, in voxel coordinates (the plan's origin and scale applied).
std::vector<glm::vec3> proxyTriangles(const LevelPlan& plan);

} // namespace yv

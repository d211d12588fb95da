// A zoom region: the unit of work every backend rasterizes and every
// destination stores (plan/zoom_plan.h plans them).
#pragma once

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace yv {

/// One box of voxels (whole bricks), processed as one unit and stored as one
/// file. Every voxel any slice can reach lies in exactly one region.
struct ZoomRegion {
    std::uint64_t id = 0;                ///< position in the plan (stable for the same inputs)
    glm::ivec3 min{0}, max{0};           ///< voxels [min, max)
    std::vector<std::uint32_t> segments; ///< segments whose slices can reach the box
    double estimatedFragments = 0.0;
};

} // namespace yv

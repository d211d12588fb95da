// A piece of a zoom region as the GL backend's passes take it, and the
// uniforms its raster and its sampling share.
#pragma once

#include "gpu/gl_program.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace yv {

/// A box of voxels (a whole number of bricks) and the segments that may touch it.
struct WorkItem {
    glm::ivec3 min, max;
    std::vector<std::uint32_t> segments;
    /// One brick drawn in several passes, each with part of its segments: its
    /// accumulators add up on the host before the brick is resolved.
    bool partial = false;

    /// Bricks along each axis.
    glm::ivec3 bricks() const { return (max - min) / 8; }
};

/// The uniforms the raster and the sampling programs share: the yarn, the
/// sampling and the region.
struct SamplingUniforms {
    float radius = 0.0f;  ///< the yarn's radius in voxels
    int supersample = 1;  ///< samples a voxel along each axis of the face
    float support = 0.0f; ///< textureSupport() of the cross-section
    /// Voxels that take samples (grid indices, max exclusive): a --bbox run's
    /// box, else the whole grid. Only the sampling program reads them.
    glm::ivec3 keepMin{0}, keepMax{0};

    void set(const GlProgram& program, const WorkItem& item) const {
        const glm::ivec3 bricks = item.bricks();
        glUniform1f(program.uniform("uRadius"), radius);
        glUniform1i(program.uniform("uSupersample"), supersample);
        glUniform1f(program.uniform("uSupport"), support);
        glUniform3i(program.uniform("uRegionMin"), item.min.x, item.min.y, item.min.z);
        glUniform3i(program.uniform("uRegionBricks"), bricks.x, bricks.y, bricks.z);
        glUniform3i(program.uniform("uKeepMin"), keepMin.x, keepMin.y, keepMin.z);
        glUniform3i(program.uniform("uKeepMax"), keepMax.x, keepMax.y, keepMax.z);
    }
};

} // namespace yv

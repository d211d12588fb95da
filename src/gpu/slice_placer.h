// Places the slices of one draw on the GPU before the draw
// (shaders/slice_setup.comp): one SliceRecord per slice, which the vertex
// shader and the sampling pass read, and where the draw is of point sprites
// each slice's sprite in the region and the terms of the raster's test.
#pragma once

#include "gpu/gl_buffer.h"
#include "gpu/gl_program.h"

#include <epoxy/gl.h>
#include <glm/vec3.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace yv {

/// The draw's inputs: segments (GpuSegment) and its draw list (segment index
/// and first instance of each entry).
struct SliceDraw {
    GLuint segments = 0, drawList = 0;
    int drawCount = 0;                 ///< entries in the draw list
    std::uint32_t uniformSlices = 0;   ///< slices of every segment when all agree, else 0
    std::uint64_t instances = 0;
};

/// The region a draw of point sprites covers, and the raster's settings
/// (shaders/slice.vert's uniforms of the same names).
struct SpriteRegion {
    GlBuffer* sprites = nullptr; ///< GpuSpriteRecord a slice, grown to fit
    float radius = 0.0f;         ///< voxel units
    float support = 0.0f;        ///< textureSupport()
    int supersample = 1;
    glm::ivec3 regionMin{0}, regionBricks{0};
    int viewport = 0;            ///< pixels a side
    int margin = 0;              ///< pixels around the region's face
};

class SlicePlacer {
  public:
    /// `spriteDefines`: the cross-section's defines (crossSectionDefines)
    /// where the draws are of point sprites; without, place() takes no
    /// SpriteRegion.
    explicit SlicePlacer(const std::optional<std::vector<std::string>>& spriteDefines = std::nullopt);
    /// Writes the draw's records into `records` (grown to fit; `gpuBytes`
    /// tracks it), and with `sprites` each slice's sprite, and orders them
    /// before later shader reads.
    void place(const SliceDraw& draw, GlBuffer& records, std::uint64_t* gpuBytes, const SpriteRegion* sprites = nullptr) const;

  private:
    GlProgram program_;
    std::optional<GlProgram> spriteProgram_; ///< with SLICE_SPRITES
    GLuint maxGroups_ = 65535;
};

} // namespace yv

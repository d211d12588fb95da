// The GPU side of a render's volume: a brick atlas (a 3D texture of 8^3
// bricks: density as 16-bit floats, and |axis| as RGBA8 when orientation is
// drawn) and an indirection texture from level brick to atlas slot. Bricks
// arrive one at a time (streamLevelBricks) and fill the atlas's slots in
// order, a row of slots along x at a time: each row goes to the GPU in one
// call once full (a call a brick cost the driver about 2.7 us each on the
// H200, a quarter of a second for 100 k bricks).
#pragma once

#include "gpu/gl_objects.h"
#include "gpu/gl_program.h"
#include "inspect/brick_level.h"

#include <cstdint>
#include <vector>

namespace yv {

/// Bytes per voxel the atlas needs: 2 for density, 4 more for orientation.
int atlasBytesPerVoxel(bool withOrientation);

class BrickAtlas {
  public:
    /// Allocates room for `plan.bricks.size()` bricks; needs a current GL
    /// context. Throws yv::Error when the driver refuses the textures.
    BrickAtlas(const LevelPlan& plan, bool withOrientation, int max3dTextureSize);

    /// Puts one brick in the next free slot (throws when the atlas is full);
    /// on the GPU once its row of slots is full, or at finish().
    void upload(const LevelBrick& brick);
    /// Uploads the last row of slots and the indirection texture; call once every brick is in.
    void finish();
    /// Every brick of a level-0 plan at once, in place of upload() and
    /// finish(): read from `source` inside `clip` on the source's threads,
    /// made halves and colours there (slot i holds plan.bricks[i]), then
    /// uploaded a row of slots a call. The same texels as upload() makes.
    void uploadLevelZero(const VolumeSource& source, const VoxelBox& clip);

    const LevelPlan& plan() const { return plan_; }
    glm::ivec3 slotsPerAxis() const { return slots_; }
    /// Sets the uniforms by which a shader finds a voxel's brick in the atlas
    /// (atlasSlots, originVoxel, levelScale, brickDims) on `program`, in use.
    void setAddressingUniforms(const GlProgram& program) const;
    std::uint64_t bricksUploaded() const { return used_; }
    /// The largest density uploaded (0 before any): an isosurface above it draws nothing.
    float densityMax() const { return densityMax_; }
    GLuint densityTexture() const { return density_.id(); }
    GLuint orientationTexture() const { return orientation_.id(); } ///< 0 without orientation
    GLuint indirectionTexture() const { return indirection_.id(); }

  private:
    LevelPlan plan_;
    bool withOrientation_;
    glm::ivec3 slots_{1};
    std::uint64_t used_ = 0;
    float densityMax_ = 0.0f;
    void uploadRow();
    void uploadIndirection();
    /// Where level brick `c` is in slotOf_ (x fastest).
    std::size_t indirectionIndex(glm::ivec3 c) const {
        return std::size_t(c.x) + std::size_t(plan_.brickDims.x) * (std::size_t(c.y) + std::size_t(plan_.brickDims.y) * std::size_t(c.z));
    }
    /// Row `row` of slots from texels laid out as upload() lays a row out.
    void uploadRowTexels(std::uint64_t row, std::uint64_t filled, const std::uint16_t* density, const std::uint8_t* colour);

    std::vector<std::uint32_t> slotOf_; ///< the indirection grid on the host, uploaded by uploadIndirection()
    /// The row of slots being filled, as the texels it covers (slots_.x * 8 x 8 x 8):
    /// density as halves, orientation as RGBA8.
    std::vector<std::uint16_t> rowDensity_;
    std::vector<std::uint8_t> rowOrientation_;
    std::uint64_t rowStart_ = 0; ///< the first slot of that row
    GlTexture density_, orientation_, indirection_;
};

} // namespace yv

// `--render splatting`: every occupied voxel of the atlas's level drawn as a
// Gaussian-kernel splat (a point sprite) with OpenGL 4.5 (the context must be
// current). Splats are composited "over", back to front: bricks sorted by
// the distance of their centres from the eye, farthest first, and within a
// brick the voxels plane by plane from the far side, the planes across the
// axis nearest the view direction. Overlapping splats of neighbouring voxels
// make this order approximate where the kernel reaches past its voxel.
#pragma once

#include "gpu/gl_buffer.h"
#include "gpu/gl_objects.h"
#include "gpu/gl_program.h"
#include "inspect/transfer_function.h"
#include "render/brick_atlas.h"
#include "render/renderer.h"
#include "render/transfer_function_texture.h"

#include <glm/vec4.hpp>

#include <vector>

namespace yv {

struct SplatSettings {
    TransferFunction transferFunction = defaultTransferFunction();
    /// Kernel: a Gaussian of this standard deviation (level voxels), cut at three of them.
    /// 1/sqrt(2 pi) gives the kernel the area of a voxel's face.
    double sigmaVoxels = 0.3989422804;
};

class SplatRenderer : public Renderer {
  public:
    /// Builds the program and learns which level brick each atlas slot holds.
    explicit SplatRenderer(const BrickAtlas& atlas, const SplatSettings& settings = {});

    std::vector<GLenum> targetFormats() const override { return {GL_RGBA32F}; }
    /// Sorts the bricks farthest first (part of the frame's time) and draws them.
    void draw(const Frame& frame) override;
    /// The voxels of the occupied bricks drawn (the empty ones are culled on the GPU).
    void describe(RenderReport& report) const override { report.splats = std::uint64_t(bricks_.size()) * 512u; }
    void setTransferFunction(const TransferFunction& tf) override { transferFunction_.update(tf); }

  private:
    void setUniforms(const Camera& camera) const;

    const BrickAtlas& atlas_;
    SplatSettings settings_;
    GlProgram program_;
    TransferFunctionTexture transferFunction_;
    GlBuffer orderBuffer_;
    GlVertexArray emptyArray_;
    std::vector<glm::ivec4> bricks_; ///< level brick (xyz) and atlas slot (w) of each occupied brick
    float maxPointSize_ = 64.0f;
};

} // namespace yv

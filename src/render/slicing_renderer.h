// `--render texture-slicing|half-angle`: slice-based volume rendering of a
// brick atlas with OpenGL 4.5 (the context must be current). Polygons where
// planes cut the level's box are drawn one after another and blended; each
// fragment samples the atlas through the indirection texture as the ray
// caster does and maps density through the same transfer function.
//  - texture slicing: planes perpendicular to the view direction, back to
//    front ("over").
//  - half-angle: planes perpendicular to the vector halfway between the view
//    and the light, in order away from the light; each slice is drawn into
//    the eye buffer, shadowed by the light buffer, then into the light
//    buffer, so the light buffer holds the opacity between the light and the
//    next slice. Where the light comes from behind the viewer the eye buffer
//    fills front to back ("under"), else back to front ("over").
#pragma once

#include "gpu/gl_buffer.h"
#include "gpu/gl_objects.h"
#include "gpu/gl_program.h"
#include "inspect/camera.h"
#include "inspect/slice_stack.h"
#include "inspect/transfer_function.h"
#include "render/brick_atlas.h"
#include "render/renderer.h"
#include "render/transfer_function_texture.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <optional>

namespace yv {

enum class SlicingMode { TextureSlicing, HalfAngle };

struct SlicingSettings {
    TransferFunction transferFunction = defaultTransferFunction();
    int slices = 0;        ///< 0: one slice per level voxel across the box's depth along the slicing direction
    LightAngles light;     ///< half-angle only
    double ambient = 0.25; ///< half-angle: the share of the light that reaches shadowed voxels too
};

class SlicingRenderer : public Renderer {
  public:
    /// Builds the programs for `mode`.
    SlicingRenderer(const BrickAtlas& atlas, SlicingMode mode, const SlicingSettings& settings = {});

    /// Float colour: thousands of thin slices each add little, which 8 bits would round away.
    std::vector<GLenum> targetFormats() const override { return {GL_RGBA32F}; }
    /// The slices facing the camera (or the half vector) and their geometry.
    void prepare(const Camera& camera) override;
    void draw(const Frame& frame) override;
    /// The planes drawn.
    void describe(RenderReport& report) const override { report.slices = std::uint64_t(stack_.first.size()); }
    void setTransferFunction(const TransferFunction& tf) override { transferFunction_.update(tf); }

  private:
    void setVolumeUniforms(const GlProgram& p, const glm::mat4& viewProjection) const;
    void drawHalfAngle(const Frame& frame) const;

    const BrickAtlas& atlas_;
    SlicingMode mode_;
    SlicingSettings settings_;
    GlProgram eyePass_, lightPass_;
    TransferFunctionTexture transferFunction_;
    // What prepare() derived from the camera.
    glm::dvec3 normal_{0.0};
    double spacing_ = 1.0;
    bool frontToBack_ = false; ///< half-angle: the eye buffer fills "under"
    glm::mat4 lightMatrix_{1.0f};
    SliceStack stack_;
    GlBuffer stackBuffer_;
    GlVertexArray stackArray_;
    std::optional<RenderTarget> light_; ///< half-angle: the opacity towards the light
};

} // namespace yv

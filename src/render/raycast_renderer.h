// `--render raycast|mip|orientation|isosurface`: ray marching through a brick
// atlas with OpenGL 4.5 (the context must be current). With empty-space
// skipping, a first pass rasterises the proxy geometry of occupied bricks
// into each pixel's entry and exit distances; without it, rays span the
// level's box.
#pragma once

#include "gpu/gl_buffer.h"
#include "gpu/gl_objects.h"
#include "gpu/gl_program.h"
#include "inspect/transfer_function.h"
#include "render/brick_atlas.h"
#include "render/renderer.h"
#include "render/transfer_function_texture.h"

#include <optional>
#include <vector>

namespace yv {

enum class RenderMode { Raycast, Mip, Orientation, Isosurface };

struct RaycastSettings {
    bool skipEmpty = true;
    bool showSamples = false; ///< the picture shows the samples taken per pixel instead (samplesImage)
    /// Read the samples taken per pixel back with each picture (samples(),
    /// meanSamples(): inspect reports them); the live view leaves them on the GPU.
    bool countSamples = true;
    TransferFunction transferFunction = defaultTransferFunction();
    double stepVoxels = 0.5; ///< march step in level voxels
    double isoValue = 0.5;   ///< Isosurface: the density the surface lies at
};

class RaycastRenderer : public Renderer {
  public:
    /// Builds the programs (for `mode`) and the proxy geometry of `atlas`'s level.
    RaycastRenderer(const BrickAtlas& atlas, RenderMode mode, const RaycastSettings& settings = {});

    /// Colour over black, and the samples taken per pixel.
    std::vector<GLenum> targetFormats() const override { return {GL_RGBA8, GL_R32F}; }
    /// The entry and exit target, the camera's size.
    void prepare(const Camera& camera) override;
    void draw(const Frame& frame) override;
    /// Reads the samples too (samples(), meanSamples()).
    PendingRgbImage startPicture(const Frame& frame) override;
    /// The proxy triangles (with empty-space skipping) and the mean samples per pixel.
    void describe(RenderReport& report) const override;
    void setTransferFunction(const TransferFunction& tf) override { transferFunction_.update(tf); }

    /// The samples taken per pixel of the last picture read, rows top first.
    const std::vector<float>& samples() const { return samples_; }
    /// Their mean over every pixel.
    double meanSamples() const { return meanSamples_; }
    /// Triangles of the occupied bricks' boundary (drawn with empty-space skipping).
    std::uint64_t proxyTriangles() const { return std::uint64_t(proxyVertices_ / 3); }

  private:
    void drawEntryDistances(const Camera& camera);
    void setMarchUniforms(const Camera& camera) const;

    const BrickAtlas& atlas_;
    RaycastSettings settings_;
    GlProgram proxy_, march_;
    GlBuffer proxyBuffer_;
    GlVertexArray proxyArray_, emptyArray_;
    GLsizei proxyVertices_ = 0;
    TransferFunctionTexture transferFunction_;
    std::optional<RenderTarget> entry_; ///< each pixel's entry and exit distances, the frame's size
    std::vector<float> samples_;
    double meanSamples_ = 0.0;
};

/// The samples-per-pixel image: black where no sample was taken, then a
/// ramp from blue through red to yellow at `maxSamples`.
RgbImage samplesImage(const std::vector<float>& samples, int width, int height, float maxSamples);

} // namespace yv

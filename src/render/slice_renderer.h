// `--render slices`: the garment's slices drawn as alpha-blended slabs with
// Lambertian shading from the fibre orientation (the paper's own view,
// section 3.5), from the same camera as the volume renders. The slices stay
// on the GPU (a buffer texture, two texels each); a frame sorts them back to
// front on every core, uploads the order as an instance attribute and draws
// them all in one instanced call (the context must be current).
#pragma once

#include "gpu/gl_buffer.h"
#include "gpu/gl_objects.h"
#include "gpu/gl_program.h"
#include "inspect/slice_instances.h"
#include "render/renderer.h"

#include <cstdint>
#include <vector>

namespace yv {

class SliceRenderer : public Renderer {
  public:
    /// Uploads `slices`; throws yv::Error when the driver's buffer textures cannot hold them.
    explicit SliceRenderer(const SliceInstances& slices);

    std::vector<GLenum> targetFormats() const override { return {GL_RGBA8}; }
    /// The back-to-front sort, on every core (timed apart from the draw).
    void prepare(const Camera& camera) override;
    /// Uploads the order and draws every slice.
    void draw(const Frame& frame) override;
    /// The slices drawn.
    void describe(RenderReport& report) const override { report.slices = slices_.count(); }

  private:
    const SliceInstances& slices_;
    GlProgram program_;
    GlBuffer sliceBuffer_, orderBuffer_;
    GlTexture sliceTexture_;
    GlVertexArray orderArray_;
    std::vector<std::uint32_t> order_;
};

} // namespace yv

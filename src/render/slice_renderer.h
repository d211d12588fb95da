// `--render slices`: the garment's slices drawn as alpha-blended slabs with
// Lambertian shading from the fibre orientation (the paper's own view,
// section 3.5), from the same camera as the volume renders. The slices stay
// on the GPU (a buffer texture, two texels each). A frame's order is made
// there too: a compute pass keys each slice by its distance from the eye
// (inspect_slices_keys.comp), a radix sort (gpu/radix_sort.h) writes the
// back-to-front order straight into the instance attribute's buffer, and
// one instanced draw takes them all; the host neither sorts nor uploads.
// (The context must be current.)
#pragma once

#include "gpu/gl_buffer.h"
#include "gpu/gl_objects.h"
#include "gpu/gl_program.h"
#include "gpu/radix_sort.h"
#include "inspect/slice_instances.h"
#include "render/renderer.h"

#include <cstdint>
#include <optional>
#include <vector>

namespace yv {

/// How the slices are ordered.
struct SliceSettings {
    /// The reference: sorted on every core of the host (sortBackToFront) and
    /// uploaded each frame, as before the sort moved to the GPU.
    bool sortOnHost = false;
};

class SliceRenderer : public Renderer {
  public:
    /// Uploads `slices`; throws yv::Error when the driver's buffer textures
    /// or storage blocks cannot hold them.
    explicit SliceRenderer(const SliceInstances& slices, const SliceSettings& settings = {});

    std::vector<GLenum> targetFormats() const override { return {GL_RGBA8}; }
    /// The back-to-front order, on the GPU (or the host, sortOnHost); waits
    /// for it, so its time is the sort's (reported apart from the draw).
    void prepare(const Camera& camera) override;
    /// Draws the slices in the order prepare() made.
    void draw(const Frame& frame) override;
    /// The slices drawn.
    void describe(RenderReport& report) const override { report.slices = drawn_; }

    /// The slice indices the last prepare() put in the draw's order (read back; for tests).
    std::vector<std::uint32_t> drawOrder();

  private:
    const SliceInstances& slices_;
    SliceSettings settings_;
    GlProgram program_, keys_;
    GlBuffer sliceBuffer_, orderBuffer_, drawCommand_;
    GlTexture sliceTexture_;
    GlVertexArray orderArray_;
    std::optional<RadixSort> sort_; ///< unless sortOnHost
    ReadbackBuffer readback_;
    std::vector<std::uint32_t> hostOrder_;
    GLuint maxGroups_ = 1;
    std::uint64_t drawn_ = 0;
};

} // namespace yv

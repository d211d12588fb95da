// `--render slices`: the garment's slices drawn as alpha-blended slabs with
// Lambertian shading from the fibre orientation (the paper's own view,
// section 3.5), from the same camera as the volume renders. The slices stay
// on the GPU (a buffer texture, two texels each). A frame's order is made
// there too: a compute pass drops the slices outside the view frustum and
// keys the others by their distance from the eye (inspect_slices_keys.comp),
// a radix sort (gpu/radix_sort.h) writes the back-to-front order of those
// kept straight into the instance attribute's buffer and their count into
// an indirect draw's command, and one instanced draw takes them; the host
// neither sorts nor uploads. Where every slab kept fits a point sprite (the
// keys pass bounds their size on screen), the draw takes one point a slab
// rather than a box of 12 triangles. By default no slab is rasterized
// where none spans too many tiles of the picture: they are composited in
// compute, tile by tile (render/slice_tiles.h). (The context must be current.)
#pragma once

#include "gpu/gl_buffer.h"
#include "gpu/gl_objects.h"
#include "gpu/gl_program.h"
#include "gpu/radix_sort.h"
#include "inspect/render_request.h"
#include "inspect/slice_instances.h"
#include "render/renderer.h"
#include "render/slice_tiles.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace yv {

/// The slices' look: extinction times the yarn's radius (a ray through the
/// axis keeps e^-4, 2 %) and the fibres' colour.
constexpr float kSliceOpacityTimesRadius = 2.0f;
inline const glm::vec3 kSliceAlbedo(0.92f, 0.78f, 0.58f);

/// How the slices are ordered and which are drawn.
struct SliceSettings {
    /// The reference: sorted on every core of the host (sortBackToFront) and
    /// uploaded each frame, every slice drawn, as before the sort moved to the GPU.
    bool sortOnHost = false;
    /// Drop the slices outside the view frustum before the sort (the GPU's order only).
    bool cull = true;
    /// Level of detail (the GPU's order only): where a yarn's slices lie
    /// closer on screen than this, draw one slab for each 2^L consecutive
    /// slices of a segment (L up to 6), as long as they are together, so
    /// that no such slab spans more pixels along the yarn than this. 0 draws
    /// every slice.
    double lodPixels = kDefaultSliceLodPixels;
    /// Composited by tiles, each slab a point sprite, or a box (the GPU's
    /// order only; SlicePrimitive says where each falls back).
    SlicePrimitive primitive = SlicePrimitive::Auto;
    /// The context is a GPU's (GlInfo::hardware()): auto composites by tiles
    /// there only (Mesa's llvmpipe composites slower than it draws points:
    /// 0.48 against 0.15 s a 320x240 frame of 10 k slices on two cores).
    bool onGpu = false;
    /// The most (slab, tile) pairs a frame composited by tiles may make
    /// (more: drawn as points or boxes); 0: defaultMaxTilePairs.
    std::uint64_t maxTilePairs = 0;
};

/// The largest point sprite the slices render draws (where the driver's
/// points reach so far): a slab wider on screen makes the frame draw boxes.
/// Larger points would mostly shade pixels their slab misses.
constexpr float kSlicePointPixels = 64.0f;

class SliceRenderer : public Renderer {
  public:
    /// Uploads `slices`; throws yv::Error when the driver's buffer textures
    /// or storage blocks cannot hold them.
    explicit SliceRenderer(const SliceInstances& slices, const SliceSettings& settings = {});

    std::vector<GLenum> targetFormats() const override { return {GL_RGBA8}; }
    /// The slabs in view and their tiles' order (waiting for a few counts),
    /// or where they are not composited by tiles, the back-to-front order,
    /// on the GPU (or the host, sortOnHost), and whether the frame's slabs
    /// fit points; queued, not waited for.
    void prepare(const Camera& camera) override;
    /// Composites the tiles prepare() ordered, or draws the slices in its
    /// order, as points where they fit: both draws are issued, and the GPU
    /// gave one of them no instances.
    void draw(const Frame& frame) override;
    /// The slices drawn in the last frame, of the garment's, and as what
    /// (read back once the frame is done).
    void describe(RenderReport& report) const override;
    /// Shade with this twist rather than the slices' own (the live view's control).
    void setTwist(double radiansPerVoxel) override { twist_ = float(radiansPerVoxel); }
    /// Draw the next frames at this level of detail (the GPU's order only; 0 or more).
    void setSliceLod(double pixels) override;

    /// The slice indices the last prepare() put in the raster draw's order
    /// (read back; for tests; empty where the frame was composited by tiles).
    std::vector<std::uint32_t> drawOrder();
    /// Per slice, the slices its slab stood for in the last prepare()
    /// (meaningful for the slices in drawOrder(); read back; for tests).
    std::vector<std::uint32_t> spans();

  private:
    const SliceInstances& slices_;
    SliceSettings settings_;
    /// What the last prepare() had drawn, as inspect_slices_choose.comp
    /// chose: both draws' instances, read once (the copy started there; it
    /// waits for the GPU where it has not ended).
    void readCounts() const;
    /// The GL state and uniforms both draws share.
    void useProgram(const GlProgram& program, const Camera& camera) const;

    GlProgram program_, pointsProgram_, keys_, choose_;
    GlBuffer sliceBuffer_, orderBuffer_, spanBuffer_, drawCommand_, largestBuffer_;
    GlTexture sliceTexture_, spanTexture_;
    GlVertexArray orderArray_;
    std::optional<RadixSort> sort_; ///< unless sortOnHost
    std::optional<SliceTiles> tiles_; ///< where the primitive allows tiles
    mutable ReadbackBuffer readback_; ///< the counts' copy, and the tests' reads
    std::vector<std::uint32_t> hostOrder_;
    GLuint maxGroups_ = 1;
    // What the last prepare() kept, read when first asked for (readCounts).
    mutable bool countsRead_ = true;
    mutable std::uint64_t drawn_ = 0;
    mutable bool drewPoints_ = false;
    bool drewTiles_ = false;
    float pointPixels_ = 0.0f;                  ///< the largest point drawn, at most kSlicePointPixels; 0: no points
    float twist_; ///< radians per voxel of yarn the fibres turn by (SliceInstances::twist unless set)
};

} // namespace yv

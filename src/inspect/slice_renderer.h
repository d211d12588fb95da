// `--render slices`: the garment's slices drawn as alpha-blended slabs with
// Lambertian shading from the fibre orientation (the paper's own view,
// section 3.5), from the same camera as the volume renders. The slices stay
// on the GPU (a buffer texture, two texels each); a frame sorts them back to
// front on every core, uploads the order as an instance attribute and draws
// them all in one instanced call (the context must be current).
#pragma once

#include "inspect/camera.h"
#include "inspect/png_image.h"
#include "inspect/slice_instances.h"

#include <memory>

namespace yv {

struct SliceFrame {
    RgbImage image;            ///< over black
    double sortSeconds = 0.0;  ///< the back-to-front sort on the host
    double drawSeconds = 0.0;  ///< upload of the order, the draw, to glFinish
};

class SliceRenderer {
  public:
    /// Uploads `slices`; throws yv::Error when the driver's buffer textures cannot hold them.
    explicit SliceRenderer(const SliceInstances& slices);
    ~SliceRenderer();
    SliceRenderer(const SliceRenderer&) = delete;
    SliceRenderer& operator=(const SliceRenderer&) = delete;
    SliceFrame render(const Camera& camera);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace yv

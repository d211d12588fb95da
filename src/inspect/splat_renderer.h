// `--render splatting`: every occupied voxel of the atlas's level drawn as a
// Gaussian-kernel splat (a point sprite) with OpenGL 4.5 (the context must be
// current). Splats are composited "over", back to front: bricks sorted by
// the distance of their centres from the eye, farthest first, and within a
// brick the voxels plane by plane from the far side, the planes across the
// axis nearest the view direction. Overlapping splats of neighbouring voxels
// make this order approximate where the kernel reaches past its voxel.
#pragma once

#include "inspect/brick_atlas.h"
#include "inspect/camera.h"
#include "inspect/png_image.h"
#include "inspect/transfer_function.h"

#include <memory>

namespace yv {

struct SplatSettings {
    TransferFunction transferFunction{};
    /// Kernel: a Gaussian of this standard deviation (level voxels), cut at three of them.
    /// 1/sqrt(2 pi) gives the kernel the area of a voxel's face.
    double sigmaVoxels = 0.3989422804;
};

struct SplatResult {
    RgbImage image;             ///< over black
    std::uint64_t splats = 0;   ///< voxels of the occupied bricks drawn (the empty ones are culled on the GPU)
    double frameSeconds = 0.0;  ///< sorting and drawing, to glFinish
};

class SplatRenderer {
  public:
    /// Builds the program and learns which level brick each atlas slot holds.
    explicit SplatRenderer(const BrickAtlas& atlas);
    ~SplatRenderer();
    SplatRenderer(const SplatRenderer&) = delete;
    SplatRenderer& operator=(const SplatRenderer&) = delete;

    SplatResult render(const Camera& camera, const SplatSettings& settings);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace yv

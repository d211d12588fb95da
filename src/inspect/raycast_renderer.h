// `--render raycast|mip|orientation|isosurface`: ray marching through a brick atlas
// with OpenGL 4.5 (the context must be current). With empty-space skipping,
// a first pass rasterises the proxy geometry of occupied bricks into each
// pixel's entry and exit distances; without it, rays span the level's box.
#pragma once

#include "inspect/brick_atlas.h"
#include "inspect/camera.h"
#include "inspect/png_image.h"
#include "inspect/transfer_function.h"

#include <memory>
#include <string>
#include <vector>

namespace yv {

enum class RenderMode { Raycast, Mip, Orientation, Isosurface };

struct RaycastSettings {
    bool skipEmpty = true;
    TransferFunction transferFunction{};
    double stepVoxels = 0.5; ///< march step in level voxels
    double isoValue = 0.5;   ///< Isosurface: the density the surface lies at
};

struct RaycastResult {
    RgbImage image;              ///< over black
    std::vector<float> samples;  ///< samples taken per pixel, rows top first
    double meanSamples = 0.0;    ///< over every pixel
    double frameSeconds = 0.0;   ///< both passes, to glFinish
    std::uint64_t proxyTriangles = 0;
};

class RaycastRenderer {
  public:
    /// Builds the programs (for `mode`) and the proxy geometry of `atlas`'s level.
    RaycastRenderer(const BrickAtlas& atlas, RenderMode mode);
    ~RaycastRenderer();
    RaycastRenderer(const RaycastRenderer&) = delete;
    RaycastRenderer& operator=(const RaycastRenderer&) = delete;

    RaycastResult render(const Camera& camera, const RaycastSettings& settings);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// The samples-per-pixel image: black where no sample was taken, then a
/// ramp from blue through red to yellow at `maxSamples`.
RgbImage samplesImage(const std::vector<float>& samples, int width, int height, float maxSamples);

} // namespace yv

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

#include "inspect/brick_atlas.h"
#include "inspect/camera.h"
#include "inspect/png_image.h"
#include "inspect/transfer_function.h"

#include <glm/vec3.hpp>

#include <memory>
#include <string>

namespace yv {

enum class SlicingMode { TextureSlicing, HalfAngle };

/// Where a directional light comes from: degrees about +z from +x, degrees above the xy plane.
struct LightAngles {
    double azimuth = 75.0, elevation = 45.0;
};

/// Parses "azimuth,elevation"; throws yv::Error saying what is wrong.
LightAngles parseLight(const std::string& text);

/// The unit vector from the volume towards the light.
glm::dvec3 towardsLight(const LightAngles& light);

struct SlicingSettings {
    TransferFunction transferFunction{};
    int slices = 0;        ///< 0: one slice per level voxel across the box's depth along the slicing direction
    LightAngles light;     ///< half-angle only
    double ambient = 0.25; ///< half-angle: the share of the light that reaches shadowed voxels too
};

struct SlicingResult {
    RgbImage image;            ///< over black
    int slices = 0;            ///< slices drawn
    double frameSeconds = 0.0; ///< every slice, to glFinish
};

class SlicingRenderer {
  public:
    /// Builds the programs for `mode`.
    SlicingRenderer(const BrickAtlas& atlas, SlicingMode mode);
    ~SlicingRenderer();
    SlicingRenderer(const SlicingRenderer&) = delete;
    SlicingRenderer& operator=(const SlicingRenderer&) = delete;

    SlicingResult render(const Camera& camera, const SlicingSettings& settings);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace yv

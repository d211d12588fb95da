// What one picture of `yarnvox inspect --render` asks for: the render mode,
// the view, the picture's size and what each mode takes (transfer function,
// cut plane, iso value, slices, light, region outlines), typed as the
// command line parsed them.
#pragma once

#include "inspect/camera.h"
#include "inspect/region_outlines.h"
#include "inspect/slice_instances.h"
#include "inspect/transfer_function.h"
#include "inspect/volume_cut.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace yv {

/// The render modes (README, "Using it").
enum class RenderKind {
    Raycast, Mip, Cut, Orientation, Slices, TextureSlicing, HalfAngle, Splatting, Isosurface, VolumetricTriangles
};

/// The mode's name as --render takes it ("raycast", "texture-slicing", ...).
const char* renderKindName(RenderKind kind);

/// Every mode, in the order --help lists them.
const std::vector<RenderKind>& renderKinds();

/// Parses a mode's name; throws yv::Error listing the names otherwise.
RenderKind parseRenderKind(const std::string& text);

/// The modes that march rays (raycast, mip, orientation, isosurface): the
/// ones that skip empty space and count samples.
bool marchesRays(RenderKind kind);

/// The modes that draw planes through the volume (texture-slicing, half-angle).
bool drawsPlanes(RenderKind kind);

/// --slice-lod's default: where a yarn's slices lie closer on screen, the
/// slices render draws one slab for several, none longer than a pixel.
constexpr double kDefaultSliceLodPixels = 1.0;

/// How the slices render draws each slab (--slice-primitive). Boxes: a box
/// of 14 vertices, 12 triangles. Points: where every slab in view fits a
/// point sprite of at most SliceRenderer's limit, one point a slab covering
/// its screen box (the fragment casts its pixel's ray through the slab: the
/// same picture), else boxes. Tiles: no raster at all, the slabs composited
/// in compute by tiles of the picture, each pixel's ray through the slabs
/// over its tile nearest first (render/slice_tiles.h; the same picture, less
/// the blend's rounding), where no slab spans more than its limit of tiles,
/// else boxes. Auto: tiles, else points, else boxes on a GPU
/// (GlInfo::hardware()); on Mesa's software rasteriser, whose compute is no
/// faster than its raster, points, else boxes. Hopper's raster sets up few
/// triangles a second next to its compute; a point is one primitive, a tile
/// none.
enum class SlicePrimitive { Auto, Tiles, Points, Boxes };

/// "auto", "tiles", "points" or "boxes"; throws yv::Error listing the names otherwise.
SlicePrimitive parseSlicePrimitive(const std::string& text);

struct RenderRequest {
    RenderKind kind = RenderKind::Raycast;
    ViewAngles view;
    int width = 800, height = 600;
    std::optional<std::uint64_t> region; ///< frame (and draw) only this zoom region
    TransferFunction transferFunction = defaultTransferFunction();
    bool skipEmpty = true;
    bool showSamples = false; ///< the picture shows samples per pixel instead
    bool countSamples = true; ///< ray casts: the samples per pixel read back for the report (RaycastSettings::countSamples)
    CutPlane cut;
    double isoValue = 0.5; ///< isosurface: the density the surface lies at
    std::uint64_t gpuBudgetBytes = 512ull << 20; ///< capped at half the free GPU memory where the driver tells
    int repeat = 1; ///< frames drawn (the same picture), for timing
    const SliceInstances* slices = nullptr; ///< Slices: the run's slices (in the source's voxel coordinates)
    double sliceLodPixels = kDefaultSliceLodPixels; ///< Slices: the level of detail (SliceSettings::lodPixels; 0: every slice)
    SlicePrimitive slicePrimitive = SlicePrimitive::Auto; ///< Slices: --slice-primitive
    std::vector<RegionHeat> outlines;       ///< region boxes drawn over the picture (not over a cut)
    int slicePlanes = 0; ///< texture-slicing, half-angle: 0 is one per level voxel along the slicing direction
    LightAngles light;   ///< half-angle
};

} // namespace yv

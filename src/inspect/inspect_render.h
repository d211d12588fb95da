// `yarnvox inspect --render`: one picture of a work directory or a .vdb.
// Picks the level of detail the GPU budget allows, streams only that
// level's bricks into a brick atlas, frames the volume (or one zoom region)
// and ray casts it (or slices or splats it: slicing_renderer.h,
// splat_renderer.h); a cut is read at full resolution on the host instead.
#pragma once

#include "inspect/camera.h"
#include "inspect/png_image.h"
#include "inspect/region_outlines.h"
#include "inspect/slice_instances.h"
#include "inspect/slicing_renderer.h"
#include "inspect/volume_cut.h"
#include "inspect/volume_source.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace yv {

enum class RenderKind {
    Raycast, Mip, Cut, Orientation, Slices, TextureSlicing, HalfAngle, Splatting, Isosurface, VolumetricTriangles
};

/// Parses raycast|mip|cut|orientation|slices|texture-slicing|half-angle|
/// splatting|isosurface|volumetric-triangles; throws yv::Error otherwise.
RenderKind parseRenderKind(const std::string& text);

struct RenderRequest {
    RenderKind kind = RenderKind::Raycast;
    ViewAngles view;
    int width = 800, height = 600;
    std::optional<std::uint64_t> region; ///< frame (and draw) only this zoom region
    std::string transferFunction = "fibre"; ///< a preset or a colour map file
    bool skipEmpty = true;
    bool showSamples = false; ///< the picture shows samples per pixel instead
    CutPlane cut;
    double isoValue = 0.5; ///< isosurface: the density the surface lies at
    std::uint64_t gpuBudgetBytes = 512ull << 20; ///< capped at half the free GPU memory where the driver tells
    int device = -1;
    int repeat = 1; ///< frames drawn (the same picture), for timing
    const SliceInstances* slices = nullptr; ///< Slices: the run's slices (in the source's voxel coordinates)
    std::vector<RegionHeat> outlines;       ///< region boxes drawn over the picture (not over a cut)
    int slicePlanes = 0; ///< texture-slicing, half-angle: 0 is one per level voxel along the slicing direction
    LightAngles light;   ///< half-angle
};

struct RenderReport {
    RgbImage image;
    std::string renderer;        ///< the GL renderer's name (empty for a cut)
    int level = 0;               ///< 0: full resolution; L: means of 2^L voxels a side
    std::uint64_t fineBricks = 0, levelBricks = 0, gpuBytes = 0, proxyTriangles = 0;
    /// Slices drawn (slices: the garment's; texture-slicing and half-angle:
    /// planes) and splats drawn (splatting).
    std::uint64_t slices = 0, splats = 0;
    std::uint64_t budgetBytes = 0; ///< the budget the level was chosen for
    double meanSamples = 0.0, loadSeconds = 0.0;
    double frameSeconds = 0.0, bestFrameSeconds = 0.0; ///< median and fastest of the repeated frames
    double sortSeconds = 0.0, bestSortSeconds = 0.0;   ///< Slices: the back-to-front sort (frame: the draw)
};

/// Renders `source` as `request` asks. Throws yv::Error (no GL context, an
/// empty volume, a region the source lacks, a budget that holds no level).
RenderReport renderVolume(const VolumeSource& source, const RenderRequest& request);

} // namespace yv

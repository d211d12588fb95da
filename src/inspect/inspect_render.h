// `yarnvox inspect --render`: one picture of a work directory or a .vdb.
// Picks the level of detail the GPU budget allows, streams only that
// level's bricks into a brick atlas, frames the volume (or one zoom region)
// and ray casts it; a cut is read at full resolution on the host instead.
#pragma once

#include "inspect/camera.h"
#include "inspect/png_image.h"
#include "inspect/volume_cut.h"
#include "inspect/volume_source.h"

#include <cstdint>
#include <optional>
#include <string>

namespace yv {

enum class RenderKind { Raycast, Mip, Cut, Orientation, Isosurface, VolumetricTriangles };

/// Parses raycast|mip|cut|orientation|isosurface|volumetric-triangles; throws yv::Error otherwise.
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
};

struct RenderReport {
    RgbImage image;
    std::string renderer;        ///< the GL renderer's name (empty for a cut)
    int level = 0;               ///< 0: full resolution; L: means of 2^L voxels a side
    std::uint64_t fineBricks = 0, levelBricks = 0, gpuBytes = 0, proxyTriangles = 0;
    std::uint64_t budgetBytes = 0; ///< the budget the level was chosen for
    double meanSamples = 0.0, loadSeconds = 0.0;
    double frameSeconds = 0.0, bestFrameSeconds = 0.0; ///< median and fastest of the repeated frames
};

/// Renders `source` as `request` asks. Throws yv::Error (no GL context, an
/// empty volume, a region the source lacks, a budget that holds no level).
RenderReport renderVolume(const VolumeSource& source, const RenderRequest& request);

} // namespace yv

#include "inspect/inspect_render.h"

#include "core/error.h"
#include "gpu/egl_context.h"
#include "inspect/brick_atlas.h"
#include "inspect/raycast_renderer.h"
#include "inspect/slice_renderer.h"
#include "inspect/splat_renderer.h"

#include <algorithm>
#include <chrono>
#include <vector>

namespace yv {

RenderKind parseRenderKind(const std::string& text) {
    if (text == "raycast") return RenderKind::Raycast;
    if (text == "mip") return RenderKind::Mip;
    if (text == "cut") return RenderKind::Cut;
    if (text == "orientation") return RenderKind::Orientation;
    if (text == "slices") return RenderKind::Slices;
    if (text == "texture-slicing") return RenderKind::TextureSlicing;
    if (text == "half-angle") return RenderKind::HalfAngle;
    if (text == "splatting") return RenderKind::Splatting;
    if (text == "isosurface") return RenderKind::Isosurface;
    if (text == "volumetric-triangles") return RenderKind::VolumetricTriangles;
    throw Error("--render '" + text +
                "': expected raycast, mip, cut, orientation, slices, texture-slicing, half-angle, splatting, "
                "isosurface or volumetric-triangles");
}

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

/// The garment's slices, framed like the volume renders.
RenderReport renderSlices(const VoxelBox& box, const RenderRequest& request) {
    if (!request.slices) throw Error("--render slices needs the run's garment (--garment FILE.bcc)");
    GlContext context(GlContextOptions{request.device, false});
    RenderReport report;
    report.renderer = context.info().renderer;
    report.slices = request.slices->count();
    const auto start = std::chrono::steady_clock::now();
    SliceRenderer renderer(*request.slices);
    report.loadSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const Camera camera = frameBox(box, request.view, request.width, request.height);
    std::vector<double> sorts, draws;
    for (int i = 0; i < request.repeat; ++i) {
        SliceFrame f = renderer.render(camera);
        sorts.push_back(f.sortSeconds), draws.push_back(f.drawSeconds);
        if (i == 0) report.image = std::move(f.image);
    }
    report.frameSeconds = median(draws), report.bestFrameSeconds = *std::min_element(draws.begin(), draws.end());
    report.sortSeconds = median(sorts), report.bestSortSeconds = *std::min_element(sorts.begin(), sorts.end());
    drawRegionOutlines(report.image, camera, request.outlines);
    return report;
}

/// texture-slicing, half-angle and splatting: `request.repeat` frames of
/// the atlas's level, framed on `box` as the ray caster frames it.
void renderSlicedOrSplatted(const BrickAtlas& atlas, const VoxelBox& box, const RenderRequest& request,
                            const TransferFunction& tf, RenderReport& report) {
    const Camera camera = frameBox(box, request.view, request.width, request.height);
    std::vector<double> frames;
    if (request.kind == RenderKind::Splatting) {
        SplatRenderer renderer(atlas);
        SplatSettings settings;
        settings.transferFunction = tf;
        for (int i = 0; i < std::max(1, request.repeat); ++i) {
            SplatResult r = renderer.render(camera, settings);
            frames.push_back(r.frameSeconds);
            report.splats = r.splats;
            report.image = std::move(r.image);
        }
    } else {
        SlicingRenderer renderer(atlas, request.kind == RenderKind::HalfAngle ? SlicingMode::HalfAngle : SlicingMode::TextureSlicing);
        SlicingSettings settings;
        settings.transferFunction = tf;
        settings.slices = request.slicePlanes;
        settings.light = request.light;
        for (int i = 0; i < std::max(1, request.repeat); ++i) {
            SlicingResult r = renderer.render(camera, settings);
            frames.push_back(r.frameSeconds);
            report.slices = std::uint64_t(r.slices);
            report.image = std::move(r.image);
        }
    }
    std::sort(frames.begin(), frames.end());
    report.frameSeconds = frames[frames.size() / 2];
    report.bestFrameSeconds = frames.front();
    drawRegionOutlines(report.image, camera, request.outlines);
}

} // namespace

RenderReport renderVolume(const VolumeSource& source, const RenderRequest& request) {
    if (source.occupiedBricks().empty()) throw Error("nothing to render: the volume has no active voxels");
    const VoxelBox box = request.region ? source.regionBounds(*request.region) : source.bounds();
    RenderReport report;
    if (request.kind == RenderKind::Cut) {
        report.image = renderCut(source, box, request.cut);
        return report;
    }
    if (request.kind == RenderKind::Slices) return renderSlices(box, request);
    if (request.kind == RenderKind::VolumetricTriangles)
        throw Error("--render volumetric-triangles draws a garment's slices (renderVolumetricTriangles), not a volume's voxels");
    if (request.kind == RenderKind::Orientation && !source.hasOrientation())
        throw Error("--render orientation: the volume has no orientation grid");
    const bool orientation = request.kind == RenderKind::Orientation;
    const TransferFunction tf = loadTransferFunction(request.transferFunction);

    GlContext context(GlContextOptions{request.device, false});
    report.renderer = context.info().renderer;
    const auto start = std::chrono::steady_clock::now();
    report.budgetBytes = request.gpuBudgetBytes;
    if (const long long free = context.queryFreeMemoryBytes(); free > 0)
        report.budgetBytes = std::min(report.budgetBytes, std::uint64_t(free) / 2);
    const LevelPlan plan =
        planLevel(source, box, report.budgetBytes, atlasBytesPerVoxel(orientation), context.info().max3dTextureSize);
    if (plan.bricks.empty()) throw Error("nothing to render: no active voxel inside the framed box");
    BrickAtlas atlas(plan, orientation, context.info().max3dTextureSize);
    streamLevelBricks(source, box, plan, orientation, [&](const LevelBrick& b) { atlas.upload(b); });
    atlas.finish();
    report.loadSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    report.level = plan.level;
    report.fineBricks = plan.fineBricks;
    report.levelBricks = plan.bricks.size();
    report.gpuBytes = plan.gpuBytes;
    if (request.kind == RenderKind::TextureSlicing || request.kind == RenderKind::HalfAngle ||
        request.kind == RenderKind::Splatting) {
        renderSlicedOrSplatted(atlas, box, request, tf, report);
        return report;
    }

    RaycastRenderer renderer(atlas, request.kind == RenderKind::Mip           ? RenderMode::Mip
                                    : request.kind == RenderKind::Orientation ? RenderMode::Orientation
                                    : request.kind == RenderKind::Isosurface  ? RenderMode::Isosurface
                                                                              : RenderMode::Raycast);
    RaycastSettings settings;
    settings.skipEmpty = request.skipEmpty;
    settings.transferFunction = tf;
    settings.isoValue = request.isoValue;
    const Camera camera = frameBox(box, request.view, request.width, request.height);
    RaycastResult r = renderer.render(camera, settings);
    std::vector<double> frames = {r.frameSeconds};
    for (int i = 1; i < request.repeat; ++i) frames.push_back(renderer.render(camera, settings).frameSeconds);
    std::sort(frames.begin(), frames.end());
    report.proxyTriangles = request.skipEmpty ? r.proxyTriangles : 0;
    report.meanSamples = r.meanSamples;
    report.frameSeconds = frames[frames.size() / 2];
    report.bestFrameSeconds = frames.front();
    if (request.showSamples) {
        const float most = r.samples.empty() ? 1.0f : *std::max_element(r.samples.begin(), r.samples.end());
        report.image = samplesImage(r.samples, request.width, request.height, most);
    } else {
        report.image = r.image;
    }
    drawRegionOutlines(report.image, camera, request.outlines);
    return report;
}

} // namespace yv

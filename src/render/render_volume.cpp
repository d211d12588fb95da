#include "render/render_volume.h"

#include "core/error.h"
#include "core/world_units.h"
#include "render/raycast_renderer.h"
#include "render/slice_renderer.h"
#include "render/slicing_renderer.h"
#include "render/splat_renderer.h"
#include "render/volumetric_triangles.h"

#include <algorithm>
#include <chrono>

namespace yv {
namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

RenderMode raycastMode(RenderKind kind) {
    switch (kind) {
    case RenderKind::Mip: return RenderMode::Mip;
    case RenderKind::Orientation: return RenderMode::Orientation;
    case RenderKind::Isosurface: return RenderMode::Isosurface;
    default: return RenderMode::Raycast;
    }
}

const BrickAtlas& atlasOf(const RenderInput& input) {
    if (!input.atlas) throw Error("this render draws a volume's voxels: it needs a brick atlas");
    return *input.atlas;
}

/// The level the budget allows (capped at half the free GPU memory where the
/// driver tells), its bricks streamed into an atlas; the report gets the
/// The atlas of `source` framed by `box`, at the finest level the budget
/// allows (capped at half the free GPU memory where the driver tells), from
/// the command's brick cache; the report gets the level, its bricks and bytes.
const BrickAtlas& loadAtlas(RenderContext& context, const VolumeSource& source, const VoxelBox& box,
                            const RenderRequest& request, RenderReport& report) {
    const GlContext& gl = context.gl();
    const bool orientation = request.kind == RenderKind::Orientation;
    report.budgetBytes = request.gpuBudgetBytes;
    if (const long long free = gl.queryFreeMemoryBytes(); free > 0)
        report.budgetBytes = std::min(report.budgetBytes, std::uint64_t(free) / 2);
    const AtlasLoad load = context.bricks().load(gl, source, box, report.budgetBytes, orientation);
    report.level = load.level;
    report.storedLevel = load.storedLevel;
    report.fineBricks = load.fineBricks;
    report.levelBricks = load.levelBricks;
    report.gpuBytes = load.gpuBytes;
    return *load.atlas;
}

/// The garment's slices, framed like the volume renders.
RenderReport renderSlices(RenderContext& context, const VoxelBox& box, const RenderRequest& request) {
    if (!request.slices) throw Error("--render slices needs the run's garment (--garment FILE.bcc)");
    RenderReport report;
    report.renderer = context.gl().info().renderer;
    const auto start = std::chrono::steady_clock::now();
    const std::unique_ptr<Renderer> renderer = makeRenderer(request, RenderInput{.slices = request.slices, .onGpu = context.gl().info().hardware()});
    report.loadSeconds = secondsSince(start);
    const Camera camera = frameBox(box, request.view, request.width, request.height);
    drawFrames(*renderer, camera, request.repeat, report);
    drawRegionOutlines(report.image, camera, request.outlines);
    return report;
}

} // namespace

std::unique_ptr<Renderer> makeRenderer(const RenderRequest& request, const RenderInput& input) {
    switch (request.kind) {
    case RenderKind::Raycast:
    case RenderKind::Mip:
    case RenderKind::Orientation:
    case RenderKind::Isosurface: {
        RaycastSettings settings;
        settings.skipEmpty = request.skipEmpty;
        settings.showSamples = request.showSamples;
        settings.countSamples = request.countSamples;
        settings.transferFunction = request.transferFunction;
        settings.isoValue = request.isoValue;
        return std::make_unique<RaycastRenderer>(atlasOf(input), raycastMode(request.kind), settings);
    }
    case RenderKind::TextureSlicing:
    case RenderKind::HalfAngle: {
        SlicingSettings settings;
        settings.transferFunction = request.transferFunction;
        settings.slices = request.slicePlanes;
        settings.light = request.light;
        const SlicingMode mode = request.kind == RenderKind::HalfAngle ? SlicingMode::HalfAngle : SlicingMode::TextureSlicing;
        return std::make_unique<SlicingRenderer>(atlasOf(input), mode, settings);
    }
    case RenderKind::Splatting: {
        SplatSettings settings;
        settings.transferFunction = request.transferFunction;
        return std::make_unique<SplatRenderer>(atlasOf(input), settings);
    }
    case RenderKind::Slices:
        if (!input.slices) throw Error("--render slices needs the run's garment (--garment FILE.bcc)");
        return std::make_unique<SliceRenderer>(
            *input.slices,
            SliceSettings{.lodPixels = request.sliceLodPixels, .primitive = request.slicePrimitive, .onGpu = input.onGpu});
    case RenderKind::VolumetricTriangles:
        if (!input.plan || !input.grid)
            throw Error("--render volumetric-triangles draws a garment's slices (renderVolumetricTriangles), not a volume's voxels");
        return std::make_unique<VolumetricTriangleRenderer>(*input.plan, *input.grid, request.transferFunction,
                                                            input.yarnDensity);
    case RenderKind::Cut: break;
    }
    throw Error("--render cut is read on the host (renderCut), not drawn");
}

RenderReport renderVolume(RenderContext& context, const VolumeSource& source, const RenderRequest& request) {
    if (source.occupiedBricks().empty()) throw Error("nothing to render: the volume has no active voxels");
    const VoxelBox box = request.region ? source.regionBounds(*request.region) : source.bounds();
    RenderReport report;
    if (request.kind == RenderKind::Cut) {
        report.image = renderCut(source, box, request.cut);
        return report;
    }
    if (request.kind == RenderKind::Slices) return renderSlices(context, box, request);
    if (request.kind == RenderKind::VolumetricTriangles)
        throw Error("--render volumetric-triangles draws a garment's slices (renderVolumetricTriangles), not a volume's voxels");
    if (request.kind == RenderKind::Orientation && !source.hasOrientation())
        throw Error("--render orientation: the volume has no orientation grid");

    const GlContext& gl = context.gl();
    report.renderer = gl.info().renderer;
    const auto start = std::chrono::steady_clock::now();
    const BrickAtlas& atlas = loadAtlas(context, source, box, request, report);
    report.loadSeconds = secondsSince(start);
    // A surface above every density drawn is an empty picture that looks like a drawing failure.
    if (request.kind == RenderKind::Isosurface && double(atlas.densityMax()) < request.isoValue)
        throw Error("--iso " + numberText(request.isoValue) + ": no voxel drawn reaches it (the densities" +
                    (report.level > 0 ? " of level " + std::to_string(report.level) : std::string()) + " are at most " +
                    numberText(atlas.densityMax()) + "): the picture would be empty; give --iso below that");
    const std::unique_ptr<Renderer> renderer = makeRenderer(request, RenderInput{.atlas = &atlas});
    const Camera camera = frameBox(box, request.view, request.width, request.height);
    drawFrames(*renderer, camera, request.repeat, report);
    drawRegionOutlines(report.image, camera, request.outlines);
    return report;
}

RenderReport renderVolumetricTriangles(RenderContext& context, const SlicePlan& plan, const VoxelGrid& grid,
                                       const VoxelBox& box, const RenderRequest& request, double yarnDensity) {
    if (plan.sliceCount == 0) throw Error("nothing to render: the garment has no slices");
    if (box.empty()) throw Error("nothing to render: the slices reach no voxel of the grid");
    RenderReport report;
    report.renderer = context.gl().info().renderer;
    RenderRequest drawn = request;
    drawn.kind = RenderKind::VolumetricTriangles;
    const std::unique_ptr<Renderer> renderer =
        makeRenderer(drawn, RenderInput{.plan = &plan, .grid = &grid, .yarnDensity = yarnDensity});
    drawFrames(*renderer, frameBox(box, request.view, request.width, request.height), request.repeat, report);
    return report;
}

} // namespace yv

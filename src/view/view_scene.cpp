#include "view/view_scene.h"

#include "core/error.h"
#include "inspect/render_request.h"
#include "render/render_volume.h"
#include "view/view_camera.h"

#include <algorithm>
#include <chrono>
#include <cstring>

namespace yv {
namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// The volume modes, in key order; the ones a volume lacks are left out by the scene.
const std::vector<RenderKind> kVolumeModes = {RenderKind::Raycast,       RenderKind::Mip,
                                              RenderKind::Isosurface,    RenderKind::Orientation,
                                              RenderKind::TextureSlicing, RenderKind::HalfAngle,
                                              RenderKind::Splatting};

} // namespace

ViewScene::ViewScene(ViewVolume volume, int device, std::uint64_t gpuBudgetBytes, double sliceLodPixels)
    : volume_(std::move(volume)), box_(volume_.source->bounds()), context_(device), budget_(gpuBudgetBytes),
      sliceLodPixels_(sliceLodPixels) {
    const GlContext& gl = context_.gl();
    rendererName_ = gl.info().renderer;
    if (const long long free = gl.queryFreeMemoryBytes(); free > 0) budget_ = std::min(budget_, std::uint64_t(free) / 2);
    // The atlas without orientation colours, loaded now: a level the budget cannot hold fails before serving.
    const AtlasLoad plain = context_.bricks().load(gl, *volume_.source, box_, budget_, false);
    for (RenderKind kind : kVolumeModes) {
        if (kind == RenderKind::Orientation && !volume_.source->hasOrientation()) continue;
        // A surface above every density drawn would be an empty picture that looks like a failure.
        if (kind == RenderKind::Isosurface && plain.atlas->densityMax() < 0.5f) continue;
        modes_.push_back(renderKindName(kind));
    }
    if (volume_.slices && !sideBySide()) modes_.push_back(renderKindName(RenderKind::Slices));
}

Renderer& ViewScene::rendererFor(const std::string& mode) {
    if (auto it = renderers_.find(mode); it != renderers_.end()) return *it->second;
    RenderRequest request;
    request.kind = parseRenderKind(mode);
    RenderInput input;
    if (request.kind == RenderKind::Slices) {
        request.slices = &*volume_.slices;
        request.sliceLodPixels = sliceLodPixels_;
        input.slices = &*volume_.slices;
    } else {
        const bool orientation = request.kind == RenderKind::Orientation;
        // The cache keeps two atlases, plain and with orientation: the renderers' stay alive.
        const AtlasLoad load = context_.bricks().load(context_.gl(), *volume_.source, box_, budget_, orientation);
        atlases_[mode] = load;
        input.atlas = load.atlas;
    }
    auto made = makeRenderer(request, input);
    Renderer& renderer = *made;
    renderers_[mode] = std::move(made);
    return renderer;
}

void ViewScene::drawInto(const std::string& mode, const ViewCamera& view, int width, int height, RgbImage& out, int x0,
                         ViewFrame& frame) {
    Renderer& renderer = rendererFor(mode);
    RenderReport report;
    drawFrames(renderer, viewCamera(box_, view, width, height), 1, report);
    frame.drawSeconds += report.frameSeconds + report.sortSeconds;
    frame.slices += report.slices;
    if (const auto it = atlases_.find(mode); it != atlases_.end()) {
        frame.level = it->second.level;
        frame.gpuBytes += it->second.gpuBytes;
    }
    for (int y = 0; y < height; ++y)
        std::memcpy(out.at(x0, y), report.image.at(0, y), std::size_t(width) * 3u);
}

ViewFrame ViewScene::render(const ViewState& state) {
    if (std::find(modes_.begin(), modes_.end(), state.mode) == modes_.end())
        throw Error("no mode '" + state.mode + "' in this view");
    const auto start = std::chrono::steady_clock::now();
    context_.gl(); // current on this thread
    ViewFrame frame;
    frame.image = RgbImage(state.width, state.height);
    if (sideBySide()) {
        // One camera for both halves: the same view of the same voxel box.
        const int left = state.width / 2;
        drawInto(renderKindName(RenderKind::Slices), state.camera, left, state.height, frame.image, 0, frame);
        drawInto(state.mode, state.camera, state.width - left, state.height, frame.image, left, frame);
    } else {
        drawInto(state.mode, state.camera, state.width, state.height, frame.image, 0, frame);
    }
    frame.renderSeconds = secondsSince(start);
    return frame;
}

void ViewScene::voxelizeInView(const ViewState&) {
    throw Error("voxelizing what the camera sees is not there yet (issue 30): the view shows the volume it opened");
}

} // namespace yv

#include "view/view_scene.h"

#include "core/error.h"
#include "core/trace.h"
#include "inspect/render_request.h"
#include "inspect/transfer_function.h"
#include "render/render_volume.h"
#include "view/view_camera.h"

#include <nlohmann/json.hpp>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <system_error>

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

/// `box` (voxels of `grid`) in world units.
RealBox worldOf(const RealBox& box, const VoxelGrid& grid) {
    return {grid.origin + box.min * grid.voxelSize, grid.origin + box.max * grid.voxelSize};
}

/// A layer's renderer (and its atlas and look) of `mode`, `coarser` levels coarser than the budget's.
std::string rendererKey(const std::string& mode, int coarser) {
    return coarser == 0 ? mode : mode + "@" + std::to_string(coarser);
}

/// The width of the ray cast's part of a frame: its right half beside the slices, else all of it.
int volumeWidth(const ViewScene& scene, const ViewState& state) {
    return scene.sideBySide() && !(state.blend && scene.blends()) ? state.width - state.width / 2 : state.width;
}

} // namespace

/// A view voxelization being drawn: its run, its volume and the atlases of its own.
struct ViewScene::DetailLayer {
    DetailRun run;
    std::unique_ptr<VolumeSource> source;
    BrickCache cache;
    VolumeLayer layer; ///< last: its renderers go before the atlases they draw
};

/// The second volume's atlases, its own: two volumes' loads would evict each other from one cache.
struct ViewScene::BesideLayer {
    BrickCache cache;
    VolumeLayer layer; ///< last: its renderers go before the atlases they draw
};

ViewScene::ViewScene(ViewVolume volume, int device, std::uint64_t gpuBudgetBytes, ViewQuality quality,
                     std::optional<ViewVolume> beside)
    : volume_(std::move(volume)), box_(volume_.source->bounds()), context_(device), budget_(gpuBudgetBytes),
      quality_(quality), movingSliceLod_(quality.lodPixels) {
    const GlContext& gl = context_.gl();
    rendererName_ = gl.info().renderer;
    if (const long long free = gl.queryFreeMemoryBytes(); free > 0) budget_ = std::min(budget_, std::uint64_t(free) / 2);
    // Two volumes share the budget (each its own atlases): half each, so two
    // need no more of the GPU than one did.
    if (beside) budget_ /= 2;
    // The atlas without orientation colours, loaded now: a level the budget cannot hold fails before serving.
    const AtlasLoad plain = context_.bricks().load(gl, *volume_.source, box_, budget_, false);
    float densityMax = plain.atlas->densityMax();
    bool orientation = volume_.source->hasOrientation();
    if (beside) {
        beside_ = std::make_unique<ViewVolume>(std::move(*beside));
        besideLayer_ = std::make_unique<BesideLayer>();
        VolumeLayer& layer = besideLayer_->layer;
        layer.source = beside_->source.get();
        layer.cache = &besideLayer_->cache;
        layer.box = layer.source->bounds();
        if (volume_.grid && beside_->grid) {
            // Both say where they lie: the same place in the world (as a view's run is mapped).
            layer.scale = volume_.grid->voxelSize / beside_->grid->voxelSize;
            layer.offset = (volume_.grid->origin - beside_->grid->origin) / beside_->grid->voxelSize;
        } else {
            // Each framed alike in its own box: centre on centre, longest side on longest side.
            const glm::dvec3 from = glm::dvec3(box_.max - box_.min), to = glm::dvec3(layer.box.max - layer.box.min);
            layer.scale = std::max({to.x, to.y, to.z}) / std::max({from.x, from.y, from.z});
            layer.offset = 0.5 * glm::dvec3(layer.box.min + layer.box.max) - layer.scale * 0.5 * glm::dvec3(box_.min + box_.max);
        }
        const AtlasLoad other = layer.cache->load(gl, *layer.source, layer.box, budget_, false);
        densityMax = std::min(densityMax, other.atlas->densityMax());
        orientation = orientation && layer.source->hasOrientation();
    }
    // The modes both volumes have.
    for (RenderKind kind : kVolumeModes) {
        if (kind == RenderKind::Orientation && !orientation) continue;
        // A surface above every density drawn would be an empty picture that looks like a failure.
        if (kind == RenderKind::Isosurface && densityMax < 0.5f) continue;
        modes_.push_back(renderKindName(kind));
    }
    if (volume_.slices && !sideBySide()) modes_.push_back(renderKindName(RenderKind::Slices));
    opened_.source = volume_.source.get();
    opened_.cache = &context_.bricks();
    opened_.box = box_;
}

ViewScene::~ViewScene() {
    context_.gl(); // the layers' textures go with the context current
    besideLayer_.reset();
    detail_.reset();
}

Renderer& ViewScene::rendererFor(VolumeLayer& layer, const std::string& mode, ViewFrame& frame, int coarser) {
    const std::string key = rendererKey(mode, coarser);
    if (auto it = layer.renderers.find(key); it != layer.renderers.end()) return *it->second;
    RenderRequest request;
    request.kind = parseRenderKind(mode);
    request.countSamples = false; // no frame shows them, and reading them back costs every frame
    RenderInput input;
    if (request.kind == RenderKind::Slices) {
        request.slices = &*volume_.slices;
        request.sliceLodPixels = quality_.lodPixels;
        request.slicePrimitive = quality_.slicePrimitive;
        input.slices = &*volume_.slices;
        input.onGpu = context_.gl().info().hardware();
    } else {
        const bool orientation = request.kind == RenderKind::Orientation;
        // The cache keeps two atlases, plain and with orientation: the renderers' stay alive.
        const auto loading = std::chrono::steady_clock::now();
        AtlasLoad load = layer.cache->load(context_.gl(), *layer.source, layer.box, budget_, orientation);
        if (coarser > 0) {
            // A quarter of the bytes a step: about a level each (a garment's surface of bricks shrinks
            // by four to eight a level).
            if (!layer.coarse) layer.coarse = std::make_unique<BrickCache>();
            const std::uint64_t bytes = std::max<std::uint64_t>(load.gpuBytes >> (2 * coarser), 1);
            load = layer.coarse->load(context_.gl(), *layer.source, layer.box, bytes, orientation);
            if (!load.fromCache)
                for (auto it = layer.renderers.begin(); it != layer.renderers.end();)
                    it = it->first.find('@') != std::string::npos ? layer.renderers.erase(it) : std::next(it);
        }
        frame.atlasSeconds += secondsSince(loading);
        layer.atlases[key] = load;
        input.atlas = load.atlas;
    }
    const auto making = std::chrono::steady_clock::now();
    std::unique_ptr<Renderer> made = makeRenderer(request, input);
    frame.rendererSeconds += secondsSince(making);
    traceSpanSince("make a renderer", making);
    Renderer& renderer = *made;
    layer.renderers[key] = std::move(made);
    layer.looks.erase(key); // a new renderer has the default look
    return renderer;
}

ViewScene::VolumeLayer& ViewScene::layerFor(const std::string& mode, const ViewCamera& view, int width, int height) {
    if (!detail_ || !volume_.grid || mode == renderKindName(RenderKind::Slices)) return opened_;
    // The view voxelization, while the camera sees no more than its box (a
    // camera that moved away sees the volume opened until it stops again).
    const RealBox seen = seenBox(box_, viewCamera(box_, view, width, height));
    if (seen.empty() || !detail_->run.plan.world.contains(worldOf(seen, *volume_.grid))) return opened_;
    return detail_->layer;
}

const std::vector<std::string>& ViewScene::transferPresets() const { return transferFunctionPresets(); }

const TransferFunction& ViewScene::transferFunction(const ViewState& state) {
    const auto key = std::make_pair(state.transfer, state.opacity);
    if (const auto it = transfers_.find(key); it != transfers_.end()) return it->second;
    // A page moving a slider makes a few dozen; a hostile one is bounded by the hub's checks, not by this cache.
    if (transfers_.size() >= 64) transfers_.clear();
    return transfers_[key] = withOpacityScale(loadTransferFunction(state.transfer), state.opacity);
}

double ViewScene::sliceLodFor(const ViewState& state) const {
    return state.moving && state.degrade ? std::max(movingSliceLod_, quality_.lodPixels) : quality_.lodPixels;
}

void ViewScene::adaptMovingSliceLod(double seconds) {
    constexpr double kCoarsest = 64.0; // SliceRenderer's slabs span at most 64 slices
    const double finest = quality_.lodPixels;
    if (seconds > quality_.movingSeconds) {
        movingSliceLod_ = std::min(kCoarsest, std::max(1.0, 2.0 * movingSliceLod_));
    } else if (seconds < quality_.movingSeconds / 4.0 && movingSliceLod_ > finest) {
        // Halved back while early; below a pixel, the level asked for.
        movingSliceLod_ = movingSliceLod_ / 2.0 < std::max(finest, 1.0) ? finest : movingSliceLod_ / 2.0;
    }
}

ViewScene::QueuedPicture ViewScene::queuePicture(const ViewState& state, const std::string& mode, int width, int height,
                                                 int x0, ViewFrame& frame, VolumeLayer* chosen) {
    VolumeLayer& layer = chosen ? *chosen : layerFor(mode, state.camera, width, height);
    QueuedPicture queued;
    queued.layer = &layer;
    queued.x0 = x0;
    queued.slices = mode == renderKindName(RenderKind::Slices);
    queued.degrading = state.moving && state.degrade;
    int coarser = !queued.slices && queued.degrading ? movingCoarser_ : 0;
    Renderer* chosenRenderer = nullptr;
    try {
        chosenRenderer = &rendererFor(layer, mode, frame, coarser);
    } catch (const Error&) {
        if (coarser == 0) throw;
        // No coarser level fits (a volume of a few bricks): the budget's level.
        coarser = movingCoarser_ = 0;
        chosenRenderer = &rendererFor(layer, mode, frame);
    }
    Renderer& renderer = *chosenRenderer;
    queued.coarser = coarser;
    queued.key = rendererKey(mode, coarser);
    if (queued.slices) {
        // The twist is in world units; the slices lie in the volume's voxels.
        if (twistable()) renderer.setTwist(state.twist * volume_.grid->voxelSize);
        frame.sliceLod = sliceLodFor(state);
        frame.degraded = frame.degraded || frame.sliceLod != quality_.lodPixels;
        renderer.setSliceLod(frame.sliceLod);
    } else if (auto& look = layer.looks[queued.key]; look != std::make_pair(state.transfer, state.opacity)) {
        renderer.setTransferFunction(transferFunction(state));
        look = {state.transfer, state.opacity};
    }
    Camera camera = mapCamera(viewCamera(box_, state.camera, width, height), layer.scale, layer.offset);
    if (besideLayer_ && &layer == &besideLayer_->layer) camera = enclosing(camera, layer.box);
    queued.inFlight = std::make_unique<PictureInFlight>(renderer, camera, context_.gl().info().hardware());
    return queued;
}

void ViewScene::takePicture(QueuedPicture& queued, RgbImage& out, ViewFrame& frame) {
    const RenderReport report = queued.inFlight->finish();
    queued.inFlight.reset();
    VolumeLayer& layer = *queued.layer;
    const double seconds = report.frameSeconds + report.sortSeconds;
    frame.drawSeconds += seconds;
    frame.slices += report.slices;
    if (queued.slices) frame.slicePrimitive = report.slicePrimitive;
    if (queued.slices && queued.degrading) adaptMovingSliceLod(seconds);
    if (!queued.slices) {
        frame.coarserLevels = queued.coarser;
        frame.degraded = frame.degraded || queued.coarser > 0;
        // Late: a level coarser next time; well early: a level finer.
        if (queued.degrading && seconds > quality_.movingSeconds) movingCoarser_ = std::min(kMaxMovingCoarser, queued.coarser + 1);
        else if (queued.degrading && seconds < quality_.movingSeconds / 4.0) movingCoarser_ = std::max(0, queued.coarser - 1);
    }
    if (const auto it = layer.atlases.find(queued.key); it != layer.atlases.end()) {
        frame.level = it->second.level;
        frame.gpuBytes += it->second.gpuBytes;
    }
    if (detail_ && &layer == &detail_->layer) frame.detail = detail_->run.id;
    for (int y = 0; y < report.image.height; ++y)
        std::memcpy(out.at(queued.x0, y), report.image.at(0, y), std::size_t(report.image.width) * 3u);
}

void ViewScene::takeFinishedDetail(ViewFrame& frame) {
    if (!voxelizer_) return;
    std::optional<DetailRun> run = voxelizer_->takeFinished();
    if (!run) return;
    const auto start = std::chrono::steady_clock::now();
    auto next = std::make_unique<DetailLayer>();
    next->run = std::move(*run);
    next->source = keptBricksSource(next->run.bricks);
    frame.openSeconds = secondsSince(start);
    traceSpanSince("open a view voxelization", start);
    next->layer.source = next->source.get();
    next->layer.cache = &next->cache;
    next->layer.box = next->source->bounds();
    // Both grids share the world: detail voxel = (origin + opened voxel * h - detail origin) / detail h.
    const VoxelGrid& opened = *volume_.grid;
    const VoxelGrid& fine = next->run.grid;
    next->layer.scale = opened.voxelSize / fine.voxelSize;
    next->layer.offset = (opened.origin - fine.origin) / fine.voxelSize;
    detail_ = std::move(next);
}

ViewFrame ViewScene::render(const ViewState& state) {
    if (std::find(modes_.begin(), modes_.end(), state.mode) == modes_.end())
        throw Error("no mode '" + state.mode + "' in this view");
    const TraceSpan span("render a view frame");
    const auto start = std::chrono::steady_clock::now();
    context_.gl(); // current on this thread
    ViewFrame frame;
    takeFinishedDetail(frame);
    frame.image = RgbImage(state.width, state.height);
    if (beside_) {
        // Two volumes, one camera: the first on the left, the second on the right, in the same mode.
        const int left = state.width / 2;
        QueuedPicture first = queuePicture(state, state.mode, left, state.height, 0, frame);
        QueuedPicture second = queuePicture(state, state.mode, state.width - left, state.height, left, frame, &besideLayer_->layer);
        takePicture(first, frame.image, frame);
        takePicture(second, frame.image, frame);
    } else if (sideBySide() && state.blend) {
        // One picture: both drawn whole, the voxels' over the slices at half weight.
        RgbImage slices(state.width, state.height);
        QueuedPicture under = queuePicture(state, renderKindName(RenderKind::Slices), state.width, state.height, 0, frame);
        QueuedPicture over = queuePicture(state, state.mode, state.width, state.height, 0, frame);
        takePicture(under, slices, frame);
        takePicture(over, frame.image, frame);
        for (std::size_t i = 0; i < frame.image.pixels.size(); ++i)
            frame.image.pixels[i] = std::uint8_t((unsigned(frame.image.pixels[i]) + unsigned(slices.pixels[i]) + 1u) / 2u);
    } else if (sideBySide()) {
        // One camera for both halves: the same view of the same voxel box.
        const int left = state.width / 2;
        QueuedPicture first = queuePicture(state, renderKindName(RenderKind::Slices), left, state.height, 0, frame);
        QueuedPicture second = queuePicture(state, state.mode, state.width - left, state.height, left, frame);
        takePicture(first, frame.image, frame);
        takePicture(second, frame.image, frame);
    } else {
        QueuedPicture only = queuePicture(state, state.mode, state.width, state.height, 0, frame);
        takePicture(only, frame.image, frame);
    }
    frame.renderSeconds = secondsSince(start);
    frame.gpuFreeBytes = context_.gl().queryFreeMemoryBytes();
    return frame;
}

std::string ViewScene::voxelizeInView(const ViewState& state, int maxSideVoxels) {
    if (!voxelizer_ || !volume_.grid)
        throw Error("voxelizing what the camera sees needs the garment: view the .bcc (yarnvox view GARMENT.bcc "
                    "[voxelize options]), or a .vdb or work directory whose run's garment is still where it names");
    const int width = volumeWidth(*this, state);
    std::string why;
    std::optional<ViewVoxelization> plan =
        planViewVoxelization(box_, *volume_.grid, viewCamera(box_, state.camera, width, state.height), maxSideVoxels,
                             kMaxViewResolution, why);
    if (!plan) throw Error(why);
    if (state.twist != volume_.twist) plan->twist = state.twist;
    const std::optional<ViewVoxelization> first = refinePass(*plan, volume_.grid->voxelSize);
    const bool started = voxelizer_->request(*plan, first);
    nlohmann::json said = {{"type", "voxelize"},
                           {"state", started ? "asked" : "already"},
                           {"voxelSize", plan->voxelSizeText},
                           {"bboxWorld", plan->boxText}};
    if (plan->twist) said["twist"] = *plan->twist;
    if (started && first) said["firstVoxelSize"] = first->voxelSizeText;
    return said.dump();
}

std::string ViewScene::saveView(bool workDir) {
    if (!voxelizer_ || !detail_)
        throw Error("nothing to save yet: stop the camera on a close view (or press v) to voxelize what it sees");
    if (detail_->run.plan.firstPass)
        throw Error("the view is still being refined: save once its final pass is shown");
    voxelizer_->save(detail_->run, workDir);
    return nlohmann::json{{"type", "voxelize"}, {"state", "saving"}, {"id", detail_->run.id}, {"workDir", workDir}}.dump();
}

const DetailRun* ViewScene::detail() const { return detail_ ? &detail_->run : nullptr; }

double ViewScene::pixelSize(const ViewState& state, bool& world) const {
    // The point looked at lies `distance` bounding-sphere radii from the eye (viewCamera).
    const double pixelVoxels =
        2.0 * state.camera.distance * viewRadius(box_) * std::tan(glm::radians(kFieldOfViewDegrees) / 2.0) / double(state.height);
    world = volume_.grid.has_value();
    return world ? pixelVoxels * volume_.grid->voxelSize : pixelVoxels;
}

} // namespace yv

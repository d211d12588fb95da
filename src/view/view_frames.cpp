#include "view/view_frames.h"

#include "core/error.h"
#include "core/trace.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <optional>

namespace yv {

ViewFrames::ViewFrames(ViewScene& scene, const FrameEncoding& encoding, int maxSideVoxels,
                       std::function<void(const std::string&)> log)
    : scene_(scene), encoding_(encoding), maxSideVoxels_(maxSideVoxels), log_(std::move(log)) {
    encoding_.movingQuality = std::min(encoding_.movingQuality, encoding_.quality);
}

Outgoing ViewFrames::draw(const ViewState& state) {
    if (!(state.moving && state.degrade)) return drawAt(state, encoding_.quality, "stats");
    // A moving frame: at the moving quality, and at half the page's width and
    // height while full-size ones would pass the bytes a second allowed. The
    // picture's camera, ruler and overlay follow the size drawn; the page
    // scales it to fit.
    ViewState drawn = state;
    if (movingHalf_) {
        drawn.width = std::max(kMinViewSide, state.width / 2);
        drawn.height = std::max(kMinViewSide, state.height / 2);
    }
    Outgoing out = drawAt(drawn, encoding_.movingQuality, "stats", movingHalf_);
    if (encoding_.movingMbitPerSecond > 0.0 && out.jpeg) {
        constexpr double kFramesPerSecond = 30.0;
        const double allowed = encoding_.movingMbitPerSecond * 1e6 / 8.0 / kFramesPerSecond; // bytes a frame
        const double bytes = double(out.jpeg->size());
        // A half-size frame has a quarter of the pixels: about a quarter of
        // the bytes (JPEG's bytes follow the pixels), so the full size would
        // take four times its bytes; back to it only with room to spare.
        if (!movingHalf_ && bytes > allowed) movingHalf_ = true;
        else if (movingHalf_ && 4.0 * bytes < 0.8 * allowed) movingHalf_ = false;
    }
    return out;
}

Outgoing ViewFrames::screenshot(const ViewState& state) {
    Outgoing out = drawAt(state, 95, "screenshot");
    out.keep = true;
    return out;
}

Outgoing ViewFrames::drawAt(const ViewState& state, int quality, const char* type, bool smaller) {
    ViewFrame frame;
    try {
        frame = scene_.render(state);
    } catch (const Error& e) {
        log_(std::string("a frame could not be drawn: ") + e.what());
        throw;
    }
    const auto start = std::chrono::steady_clock::now();
    std::optional<TraceSpan> encoding(std::in_place, "encode a view frame");
    auto jpeg = std::make_shared<std::vector<std::uint8_t>>(encoder_.encode(frame.image, quality));
    encoding.reset();
    const double encodeSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    nlohmann::json detail = nullptr;
    if (const DetailRun* run = scene_.detail())
        detail = {{"id", run->id},
                  {"voxelSize", run->plan.voxelSizeText},
                  {"bboxWorld", run->plan.boxText},
                  {"activeVoxels", run->activeVoxels},
                  {"seconds", run->seconds},
                  {"command", run->command},
                  {"shown", frame.detail == run->id},
                  {"final", !run->plan.firstPass}};
    bool world = false;
    const double pixel = scene_.pixelSize(state, world);
    const nlohmann::json stats = {{"type", type},
                                  {"frame", ++frames_},
                                  {"seq", state.camera.seq},
                                  {"mode", state.mode},
                                  {"blend", state.blend && scene_.blends()},
                                  {"transfer", state.transfer},
                                  {"opacity", state.opacity},
                                  {"twist", state.twist},
                                  {"quality", quality},
                                  {"width", state.width},
                                  {"height", state.height},
                                  {"renderMs", 1e3 * frame.renderSeconds},
                                  {"drawMs", 1e3 * frame.drawSeconds},
                                  {"openMs", 1e3 * frame.openSeconds},
                                  {"atlasMs", 1e3 * frame.atlasSeconds},
                                  {"rendererMs", 1e3 * frame.rendererSeconds},
                                  {"encodeMs", 1e3 * encodeSeconds},
                                  {"bytes", jpeg->size()},
                                  {"activeVoxels", scene_.volume().activeVoxels},
                                  {"level", frame.level},
                                  {"slices", frame.slices},
                                  {"sliceLod", frame.sliceLod >= 0.0 ? nlohmann::json(frame.sliceLod) : nlohmann::json()},
                                  {"slicePrimitive", frame.slicePrimitive.empty() ? nlohmann::json() : nlohmann::json(frame.slicePrimitive)},
                                  {"moving", state.moving},
                                  {"degrade", state.degrade},
                                  {"degraded", frame.degraded || smaller},
                                  {"coarserLevels", frame.coarserLevels},
                                  {"gpuBytes", frame.gpuBytes},
                                  {"gpuFreeBytes", frame.gpuFreeBytes},
                                  {"detail", detail},
                                  {"pixelSize", pixel},
                                  {"pixelUnits", world ? "world" : "voxels"}};
    return Outgoing{stats.dump(), std::move(jpeg)};
}

std::string helloText(const ViewScene& scene, const ViewState& initial) {
    return nlohmann::json{{"type", "hello"},
                          {"modes", scene.modes()},
                          {"mode", initial.mode},
                          {"sideBySide", scene.sideBySide()},
                          {"name", scene.volume().name},
                          {"beside", scene.beside() ? nlohmann::json(scene.beside()->name) : nlohmann::json()},
                          {"renderer", scene.renderer()},
                          {"activeVoxels", scene.volume().activeVoxels},
                          {"voxelSize", scene.volume().grid ? nlohmann::json(scene.volume().grid->voxelSize) : nlohmann::json()},
                          {"transferPresets", scene.transferPresets()},
                          {"transfer", initial.transfer},
                          {"opacity", initial.opacity},
                          {"twist", scene.twistable() ? nlohmann::json(initial.twist) : nlohmann::json()},
                          {"yarnRadius", scene.twistable() && scene.volume().slices
                                             ? nlohmann::json(scene.volume().slices->radius * scene.volume().grid->voxelSize)
                                             : nlohmann::json()},
                          {"width", initial.width},
                          {"height", initial.height}}
        .dump();
}

} // namespace yv

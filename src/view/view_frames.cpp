#include "view/view_frames.h"

#include "core/error.h"

#include <nlohmann/json.hpp>

#include <chrono>

namespace yv {

ViewFrames::ViewFrames(ViewScene& scene, int jpegQuality, std::function<void(const std::string&)> log)
    : scene_(scene), quality_(jpegQuality), log_(std::move(log)) {}

Outgoing ViewFrames::draw(const ViewState& state) {
    ViewFrame frame;
    try {
        frame = scene_.render(state);
    } catch (const Error& e) {
        log_(std::string("a frame could not be drawn: ") + e.what());
        throw;
    }
    const auto start = std::chrono::steady_clock::now();
    auto jpeg = std::make_shared<std::vector<std::uint8_t>>(encoder_.encode(frame.image, quality_));
    const double encodeSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const nlohmann::json stats = {{"type", "stats"},
                                  {"frame", ++frames_},
                                  {"seq", state.camera.seq},
                                  {"mode", state.mode},
                                  {"width", state.width},
                                  {"height", state.height},
                                  {"renderMs", 1e3 * frame.renderSeconds},
                                  {"drawMs", 1e3 * frame.drawSeconds},
                                  {"encodeMs", 1e3 * encodeSeconds},
                                  {"bytes", jpeg->size()},
                                  {"activeVoxels", scene_.volume().activeVoxels},
                                  {"level", frame.level},
                                  {"slices", frame.slices},
                                  {"gpuBytes", frame.gpuBytes}};
    return Outgoing{stats.dump(), std::move(jpeg)};
}

std::string helloText(const ViewScene& scene, const ViewState& initial) {
    return nlohmann::json{{"type", "hello"},
                          {"modes", scene.modes()},
                          {"mode", initial.mode},
                          {"sideBySide", scene.sideBySide()},
                          {"name", scene.volume().name},
                          {"renderer", scene.renderer()},
                          {"activeVoxels", scene.volume().activeVoxels},
                          {"width", initial.width},
                          {"height", initial.height}}
        .dump();
}

} // namespace yv

#include "view/view_run.h"

#include "core/error.h"
#include "view/view_frames.h"
#include "view/view_hub.h"

#include <atomic>
#include <exception>
#include <filesystem>
#include <future>
#include <optional>
#include <thread>

namespace yv {

void runView(const ViewRequest& request, const std::function<void(int port)>& ready,
             const std::function<bool()>& stopWanted, const std::function<void(const std::string&)>& log) {
    std::error_code ec;
    if (!std::filesystem::exists(request.input, ec)) throw Error(request.input + ": no such file or directory");
    if (!request.beside.empty() && !std::filesystem::exists(request.beside, ec))
        throw Error("--beside " + request.beside + ": no such file or directory");
    if (!std::filesystem::is_directory(request.saveDir, ec))
        throw Error("--save-dir " + request.saveDir + ": no such directory (the view's voxelizations are saved there)");
    // The hub outlives the server: a session closed as the server goes leaves it.
    std::optional<ViewHub> hub;
    ViewServer server(request.server, log);

    std::promise<std::string> opened; // the hello text, once the scene can draw
    std::atomic<bool> renderFailed{false};
    std::string renderError;
    std::thread render([&] {
        bool serving = false;
        try {
            // The scene and its GL context live and die on this thread.
            ViewVolume volume = openViewVolume(request.input, request.voxelize, log);
            std::optional<ViewVolume> beside;
            if (!request.beside.empty()) beside.emplace(openViewVolume(request.beside, request.voxelize, log));
            ViewScene scene(std::move(volume), request.device, request.gpuBudgetBytes, request.quality, std::move(beside));
            ViewFrames frames(scene, request.encoding, request.maxSideVoxels, log);
            ViewState initial = request.initial;
            initial.mode = scene.modes().front();
            initial.twist = scene.twist();
            hub.emplace(ViewControls{scene.modes(), scene.transferPresets(), scene.twistable()}, initial);
            // Voxelize what the camera sees, where the garment is known; after
            // the scene, so its runs stop before the scene (which they redraw) goes.
            std::optional<ViewVoxelizer> voxelizer;
            if (scene.volume().voxelizeJob && scene.volume().grid) {
                VoxelizeJob base = *scene.volume().voxelizeJob;
                ViewVoxelizer::Listener listener{[&] { hub->redrawAll(); },
                                                 [&](const std::string& text) { hub->broadcast(Outgoing{text, nullptr}); }};
                voxelizer.emplace(std::move(base), request.saveDir, std::move(listener));
                scene.attachVoxelizer(&*voxelizer);
            }
            opened.set_value(helloText(scene, initial));
            serving = true;
            hub->run(frames);
        } catch (...) {
            if (!serving) return opened.set_exception(std::current_exception());
            try {
                throw;
            } catch (const std::exception& e) {
                renderError = e.what();
            }
            renderFailed = true;
        }
    });
    std::string hello;
    try {
        hello = opened.get_future().get();
    } catch (...) {
        render.join();
        throw;
    }
    try {
        ready(server.port());
        server.serve(*hub, hello, [&] { return renderFailed || stopWanted(); });
    } catch (...) {
        hub->stop();
        render.join();
        throw;
    }
    hub->stop();
    render.join();
    if (renderFailed) throw Error("the render thread stopped: " + renderError);
}

} // namespace yv

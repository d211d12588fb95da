// `yarnvox view`: a live view of a volume or a garment in a web browser. The
// command parses its options into a ViewRequest (src/view/view_run.h), says
// where the page is and how to reach it over SSH, and serves until Ctrl-C
// or SIGTERM.
#include "cli/commands.h"
#include "cli/option_checks.h"
#include "cli/option_words.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/voxelize_settings.h"
#include "inspect/render_request.h"
#include "view/view_run.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>
#include <memory>

namespace yv {
namespace {

struct ViewArgs {
    ViewRequest request;
    std::string size = "960x540";
    std::string slicePrimitive = "auto"; ///< --slice-primitive
};

/// "WxH", each within the frame limits the page's size messages have too.
void parseFrameSize(const std::string& text, ViewState& state) {
    int w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || x != 'x' || w < kMinViewSide ||
        h < kMinViewSide || w > kMaxViewSide || h > kMaxViewSide)
        throw Error("--size '" + text + "': expected WIDTHxHEIGHT, each from " + std::to_string(kMinViewSide) + " to " +
                    std::to_string(kMaxViewSide) + " pixels");
    state.width = w;
    state.height = h;
}

/// The options of `voxelize` a garment's view takes (the grid, the slices, the backend).
void addVoxelizeOptions(CLI::App* cmd, VoxelizeJob& job) {
    auto* res = cmd->add_option("--resolution", job.resolution,
                                "A garment: voxels on the longest axis of its padded box (default 256)")
                    ->check(wholeNumber(8, 1 << 20));
    cmd->add_option("--voxel-size", job.voxelSize, "A garment: voxel edge length, world units (instead of --resolution)")
        ->check(worldLength())
        ->excludes(res);
    cmd->add_option("--yarn-radius", job.yarnRadius, "A garment: yarn radius, world units (default: as voxelize)")
        ->check(worldLength());
    auto* perSegment = cmd->add_option("--slices-per-segment", job.slicesPerSegment, "A garment: slices per curve segment")
                           ->check(wholeNumber(1, 100000));
    cmd->add_option("--slice-spacing", job.spacing, "A garment: distance between slices, world units")
        ->check(worldLength())
        ->excludes(perSegment);
    cmd->add_option("--twist", job.twist, "A garment: yarn twist, radians per world unit of yarn length")
        ->check(finiteNumber(kMaxTwist));
    cmd->add_option("--cross-section", job.crossSection, "A garment: fibers, disk, or FILE.png (alpha = density)")
        ->capture_default_str();
    cmd->add_option("--backend", job.backend, "A garment: auto, gl or cpu (as voxelize)")
        ->default_str("auto")
        ->transform(oneOf(kBackendWords));
    cmd->add_option("--supersample", job.supersample, "A garment: samples per voxel face along each axis")
        ->capture_default_str()
        ->check(wholeNumber(1, kMaxSupersample));
}

void runViewCommand(ViewArgs& a) {
    parseFrameSize(a.size, a.request.initial);
    a.request.quality.slicePrimitive = parseSlicePrimitive(a.slicePrimitive);
    ViewRequest& r = a.request;
    if (r.voxelize.resolution == 0 && r.voxelize.voxelSize == 0.0) r.voxelize.resolution = 256;
    r.voxelize.device = r.device;
    const auto log = [](const std::string& line) {
        std::fprintf(stderr, "yarnvox view: %s\n", line.c_str());
        std::fflush(stderr);
    };
    // NVIDIA's driver spins a core while it waits for the GPU (glFinish, the
    // readback): a view that waits on every frame would keep a core busy at
    // any frame rate. Yielding costs no frame time measured here (README,
    // "Live view in the browser"); a user's own setting wins.
    setenv("__GL_YIELD", "USLEEP", 0);
    const InterruptScope signals;
    runView(
        r,
        [&](int port) {
            const std::string host = r.server.bind.find(':') != std::string::npos ? "[" + r.server.bind + "]" : r.server.bind;
            std::printf("yarnvox view: %s at http://%s:%d/\n", r.input.c_str(), host.c_str(), port);
            std::printf("  from another machine: ssh -L %d:127.0.0.1:%d HOST, then open http://127.0.0.1:%d/\n", port,
                        port, port);
            if (r.server.bind != "127.0.0.1" && r.server.bind != "::1")
                std::printf("  note: --bind %s lets anyone who reaches this machine see the view (no password)\n",
                            r.server.bind.c_str());
            std::printf("  Ctrl-C stops it\n");
            std::fflush(stdout);
        },
        [] { return interruptSignal() != 0; }, log);
    std::printf("yarnvox view: stopped by %s\n", interruptSignalName().c_str());
}

} // namespace

void addViewCommand(CLI::App& app) {
    auto* cmd = app.add_subcommand("view", "Live view in a web browser: a .vdb, a work directory, or a garment "
                                           "(voxelized first), served on one port");
    auto a = std::make_shared<ViewArgs>();
    cmd->add_option("input", a->request.input, "A .vdb, a work directory, or a .bcc garment")->required();
    cmd->add_option("--port", a->request.server.port, "TCP port (0: any free one, printed)")
        ->capture_default_str()
        ->check(wholeNumber(0, 65535));
    cmd->add_option("--bind", a->request.server.bind,
                    "Address to listen on (default 127.0.0.1: this machine only; reach it with ssh -L)")
        ->capture_default_str();
    cmd->add_option("--device", a->request.device, "EGL device index (default: first GPU, else llvmpipe)")
        ->check(wholeNumber(0, 1023));
    cmd->add_option("--size", a->size, "Frame size until the page sends its own, WIDTHxHEIGHT")->capture_default_str();
    cmd->add_option("--quality", a->request.encoding.quality, "JPEG quality of the frames, 1 to 100")
        ->capture_default_str()
        ->check(wholeNumber(1, 100));
    cmd->add_option("--moving-quality", a->request.encoding.movingQuality,
                    "JPEG quality of the frames drawn while the camera moves, 1 to 100 (at most --quality; the "
                    "frame after it stops, and every frame with the page's g key, at --quality)")
        ->capture_default_str()
        ->check(wholeNumber(1, 100));
    cmd->add_option("--moving-mbit", a->request.encoding.movingMbitPerSecond,
                    "While the camera moves, the megabits a second (at 30 frames a second) its frames may take: a "
                    "frame over it makes the next moving ones half as wide and high, scaled up by the page (0: "
                    "never smaller; the frame after the camera stops is at the page's size)")
        ->capture_default_str()
        ->check(finiteRange(0.0, 1e6));
    cmd->add_option("--slice-lod", a->request.quality.lodPixels,
                    "The slices' level of detail, in pixels: where a yarn's slices lie closer on screen, one slab is "
                    "drawn for 2, 4, ... 64 consecutive slices, none longer than this (0: every slice)")
        ->capture_default_str()
        ->check(finiteRange(0.0, 1e6));
    cmd->add_option("--slice-primitive", a->slicePrimitive,
                    "How the slices' slabs are drawn: tiles (composited in compute), points, boxes, or auto (tiles "
                    "on a GPU, points on llvmpipe; each falls back where a frame's slabs do not fit it); as inspect's")
        ->capture_default_str();
    cmd->add_option_function<double>(
           "--moving-ms", [a](double ms) { a->request.quality.movingSeconds = ms / 1e3; },
           "While the camera moves, the milliseconds each half of a frame (the slices, the volume) may take: a "
           "later frame draws fewer slices or a coarser level of the volume until the camera stops (default 8: "
           "half a frame at 60 a second; the page's g key turns this off)")
        ->check(finiteRange(0.0, 1e6));
    cmd->add_option("--beside", a->request.beside,
                    "A second .vdb, work directory or garment, drawn on the right in the same mode with the same "
                    "camera (where both record where they lie, the same place in the world)");
    cmd->add_option("--save-dir", a->request.saveDir,
                    "A garment: where the s and W keys save the view's voxelization (a .vdb, a work directory)")
        ->capture_default_str();
    cmd->add_option("--view-voxels", a->request.maxSideVoxels,
                    "A garment: the most voxels along the longest side of what the camera sees when it is voxelized")
        ->capture_default_str()
        ->check(wholeNumber(16, 8192));
    addVoxelizeOptions(cmd, a->request.voxelize);
    cmd->callback([a] { runViewCommand(*a); });
}

} // namespace yv

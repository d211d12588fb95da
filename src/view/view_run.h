// `yarnvox view` as one call: the port bound, the input opened (a garment
// voxelized first) and drawn on a render thread of its own, the address
// said, and the page served until asked to stop. The CLI parses options
// into a ViewRequest; tests run it in-process with their own stop.
#pragma once

#include "pipeline/voxelize_job.h"
#include "view/view_frames.h"
#include "view/view_scene.h"
#include "view/view_server.h"

#include <cstdint>
#include <functional>
#include <string>

namespace yv {

struct ViewRequest {
    std::string input;         ///< a .vdb, a work directory or a .bcc garment
    std::string beside;        ///< --beside: a second one, drawn on the right with the same camera ("" none)
    ViewServerOptions server;  ///< --bind, --port
    int device = -1;           ///< --device: EGL device index (-1: the first GPU, else llvmpipe)
    ViewState initial;         ///< --size; a new page's camera and mode until it sends its own
    VoxelizeJob voxelize;      ///< how a garment is voxelized (its input and output are set by the view)
    std::uint64_t gpuBudgetBytes = 512ull << 20;
    ViewQuality quality;       ///< --slice-lod, --moving-ms
    FrameEncoding encoding;    ///< --quality, --moving-quality, --moving-mbit
    std::string saveDir = "."; ///< --save-dir: where the view's voxelizations are saved
    int maxSideVoxels = 1024;  ///< --view-voxels: a view voxelization's longest side, in voxels
};

/// Runs the view. `ready(port)` is called once the page is served (the
/// address can be said); `stopWanted()` is asked every 100 ms; `log` gets
/// one line at a time (refusals, notes). Throws yv::Error before anything is
/// served (a port in use, a missing or unreadable input, no GL context), or
/// when the render thread fails while serving.
void runView(const ViewRequest& request, const std::function<void(int port)>& ready,
             const std::function<bool()>& stopWanted, const std::function<void(const std::string&)>& log);

} // namespace yv

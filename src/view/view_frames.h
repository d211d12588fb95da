// The render thread's FrameSource: a view state drawn by the scene, encoded
// as JPEG, and the stats text the page's overlay shows before it; the
// server's first words to a page (hello). Text messages, server to page:
//   {"type":"hello", "modes":[...], "mode", "sideBySide", "name", "beside" (the second volume's name, or null),
//    "renderer", "activeVoxels",
//    "voxelSize" (world units; null where the volume's place in the world is not known), "width", "height"}
//   {"type":"stats", "frame", "seq", "mode", "blend", "width", "height", "renderMs", "drawMs", "encodeMs", "bytes",
//    "activeVoxels", "level", "slices", "sliceLod" and "slicePrimitive" (null: no slices drawn), "moving", "degrade", "degraded",
//    "gpuBytes", "gpuFreeBytes" (-1: unknown), "detail",
//    "pixelSize" (a pixel's width at the point looked at), "pixelUnits" ("world" or "voxels")}   (a binary JPEG message follows)
//   {"type":"notice", "text"}                         (a refusal, or what could not be drawn)
//   {"type":"screenshot", ...the stats' fields}       (a binary JPEG message follows)
//   {"type":"voxelize", "state", ...}                 (voxelize what the camera sees: asked,
//                                                       already, running, dropped (given up for a
//                                                       newer view), failed, saving, saved)
// A frame's "detail" is null, or the view voxelization taken last: "id",
// "voxelSize", "bboxWorld", "activeVoxels", "seconds", "command", and
// "shown" (this frame draws it).
#pragma once

#include "view/jpeg_frame.h"
#include "view/view_hub.h"
#include "view/view_scene.h"

#include <cstdint>
#include <string>

namespace yv {

class ViewFrames : public FrameSource {
  public:
    /// `log`: a line for each frame that could not be drawn.
    /// `maxSideVoxels`: the largest view voxelization, voxels along its longest side.
    /// `movingQuality`: the JPEG quality of a frame whose camera moves and may degrade.
    ViewFrames(ViewScene& scene, int jpegQuality, int movingQuality, int maxSideVoxels,
               std::function<void(const std::string&)> log);
    /// The frame's stats, its quality in them: fewer bytes while the camera moves (ViewState::degrade).
    Outgoing draw(const ViewState& state) override {
        return drawAt(state, state.moving && state.degrade ? movingQuality_ : quality_, "stats");
    }
    Outgoing voxelizeInView(const ViewState& state) override {
        return Outgoing{scene_.voxelizeInView(state, maxSideVoxels_), nullptr};
    }
    Outgoing saveView(bool workDir) override { return Outgoing{scene_.saveView(workDir), nullptr}; }
    /// The frame's stats as {"type":"screenshot", ...}, at JPEG quality 95, kept until sent.
    Outgoing screenshot(const ViewState& state) override;

  private:
    Outgoing drawAt(const ViewState& state, int quality, const char* type);

    ViewScene& scene_;
    JpegEncoder encoder_;
    int quality_, movingQuality_, maxSideVoxels_;
    std::function<void(const std::string&)> log_;
    std::uint64_t frames_ = 0;
};

/// The hello text a page gets when it connects.
std::string helloText(const ViewScene& scene, const ViewState& initial);

} // namespace yv

// The render thread's FrameSource: a view state drawn by the scene, encoded
// as JPEG, and the stats text the page's overlay shows before it; the
// server's first words to a page (hello). Text messages, server to page:
//   {"type":"hello", "modes":[...], "mode", "sideBySide", "name", "beside" (the second volume's name, or null),
//    "renderer", "activeVoxels",
//    "voxelSize" (world units; null where the volume's place in the world is not known), "width", "height"}
//   {"type":"stats", "frame", "seq", "mode", "blend", "width", "height" (the picture's: half the page's for a
//    moving frame over --moving-mbit), "quality", "renderMs", "drawMs", "encodeMs", "bytes",
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

/// How frames are encoded: fewer bytes while the camera moves and frames may
/// degrade (ViewState::degrade), the page's size and --quality once it stops.
struct FrameEncoding {
    int quality = 85; ///< --quality
    /// --moving-quality: the JPEG quality of frames drawn while the camera
    /// moves and the page lets them degrade (at most quality): the frame
    /// after the camera stops comes at quality.
    int movingQuality = 70;
    /// --moving-mbit: the megabits a second, at 30 frames a second, moving
    /// frames may take: one that takes more makes the next moving frames half
    /// as wide and high (the page scales them to its size) until a half-size
    /// one shows the full size would fit again (0: never smaller).
    double movingMbitPerSecond = 25.0;
};

class ViewFrames : public FrameSource {
  public:
    /// `log`: a line for each frame that could not be drawn.
    /// `maxSideVoxels`: the largest view voxelization, voxels along its longest side.
    ViewFrames(ViewScene& scene, const FrameEncoding& encoding, int maxSideVoxels,
               std::function<void(const std::string&)> log);
    /// The frame's stats, its quality and size in them.
    Outgoing draw(const ViewState& state) override;
    Outgoing voxelizeInView(const ViewState& state) override {
        return Outgoing{scene_.voxelizeInView(state, maxSideVoxels_), nullptr};
    }
    Outgoing saveView(bool workDir) override { return Outgoing{scene_.saveView(workDir), nullptr}; }
    /// The frame's stats as {"type":"screenshot", ...}, at JPEG quality 95, kept until sent.
    Outgoing screenshot(const ViewState& state) override;

  private:
    /// `smaller`: drawn at less than the page's size (counts as degraded).
    Outgoing drawAt(const ViewState& state, int quality, const char* type, bool smaller = false);

    ViewScene& scene_;
    JpegEncoder encoder_;
    FrameEncoding encoding_;
    int maxSideVoxels_;
    bool movingHalf_ = false; ///< moving frames are drawn at half the page's width and height
    std::function<void(const std::string&)> log_;
    std::uint64_t frames_ = 0;
};

/// The hello text a page gets when it connects.
std::string helloText(const ViewScene& scene, const ViewState& initial);

} // namespace yv

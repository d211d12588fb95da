// The render thread's FrameSource: a view state drawn by the scene, encoded
// as JPEG, and the stats text the page's overlay shows before it; the
// server's first words to a page (hello). Text messages, server to page:
//   {"type":"hello", "modes":[...], "mode", "sideBySide", "name", "renderer", "activeVoxels", "width", "height"}
//   {"type":"stats", "frame", "seq", "mode", "width", "height", "renderMs", "drawMs", "encodeMs", "bytes",
//    "activeVoxels", "level", "slices", "gpuBytes"}   (a binary JPEG message follows)
//   {"type":"notice", "text"}                         (a refusal, or what could not be drawn)
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
    ViewFrames(ViewScene& scene, int jpegQuality, std::function<void(const std::string&)> log);
    Outgoing draw(const ViewState& state) override;
    void voxelizeInView(const ViewState& state) override { scene_.voxelizeInView(state); }

  private:
    ViewScene& scene_;
    JpegEncoder encoder_;
    int quality_;
    std::function<void(const std::string&)> log_;
    std::uint64_t frames_ = 0;
};

/// The hello text a page gets when it connects.
std::string helloText(const ViewScene& scene, const ViewState& initial);

} // namespace yv

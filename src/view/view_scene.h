// The GL side of `yarnvox view`: the renderers of inspect kept alive between
// frames (the bricks loaded into the atlas once, the slices uploaded once),
// and one frame drawn from a view state. A garment's frame is two pictures
// side by side with one camera: its slices on the left, the ray cast (or the
// mode chosen) of its voxelization on the right. Everything here runs on the
// one render thread that made the scene (the GL context is current there).
#pragma once

#include "inspect/render_request.h"
#include "render/render_context.h"
#include "render/renderer.h"
#include "view/view_message.h"
#include "view/view_volume.h"

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace yv {

/// What one frame shows.
struct ViewState {
    ViewCamera camera;
    std::string mode = "raycast";
    int width = 960, height = 540;
    bool operator==(const ViewState&) const = default;
};

/// One frame drawn, with what the page's overlay shows about it.
struct ViewFrame {
    RgbImage image;
    double renderSeconds = 0.0; ///< the frame's host and GPU work, readback included
    double drawSeconds = 0.0;   ///< the renderers' draw calls to glFinish (the slices' also their sort)
    int level = 0;              ///< the level of detail drawn
    std::uint64_t slices = 0, gpuBytes = 0;
};

class ViewScene {
  public:
    /// Takes the opened volume; makes the GL context on `device` on the
    /// calling thread and loads the atlas (the level `gpuBudgetBytes` holds).
    /// The slices are drawn at the level of detail `sliceLodPixels`
    /// (SliceSettings::lodPixels). Throws yv::Error (no GL context, a budget
    /// that holds no level).
    ViewScene(ViewVolume volume, int device, std::uint64_t gpuBudgetBytes,
              double sliceLodPixels = kDefaultSliceLodPixels);

    /// The modes one key away, in key order ("raycast" first).
    const std::vector<std::string>& modes() const { return modes_; }
    bool sideBySide() const { return volume_.garment && volume_.slices.has_value(); }
    const ViewVolume& volume() const { return volume_; }
    /// The GL renderer's name.
    const std::string& renderer() const { return rendererName_; }

    /// Draws `state` (its mode one of modes()). Throws yv::Error on a GL error.
    ViewFrame render(const ViewState& state);

    /// Where voxelize-what-the-camera-sees goes (issue 30): the region in view
    /// voxelized at the view's resolution and swapped into the ray cast. Not
    /// there yet: says so, as a yv::Error, and changes nothing.
    void voxelizeInView(const ViewState& state);

  private:
    Renderer& rendererFor(const std::string& mode);
    void drawInto(const std::string& mode, const ViewCamera& camera, int width, int height, RgbImage& out, int x0,
                  ViewFrame& frame);

    ViewVolume volume_;
    VoxelBox box_;
    RenderContext context_;
    std::uint64_t budget_;
    double sliceLodPixels_;
    std::string rendererName_;
    std::vector<std::string> modes_;
    std::map<std::string, std::unique_ptr<Renderer>> renderers_;
    std::map<std::string, AtlasLoad> atlases_; ///< by mode: the one its renderer draws
};

} // namespace yv

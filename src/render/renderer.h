// The one interface of inspect's GL renderers (ray casting, slicing,
// splatting, the run's slices, volumetric triangles). A renderer is made for
// what it draws and how (its mode's settings) on the context it is given;
// drawFrames then owns everything a frame shares: the picture's render
// target, binding and clearing it, the timing to glFinish, the readback and
// leaving the context as it found it for the next picture.
#pragma once

#include "inspect/camera.h"
#include "inspect/png_image.h"
#include "inspect/transfer_function.h"
#include "gpu/gpu_timer.h"
#include "render/render_target.h"

#include <epoxy/gl.h>

#include <cstdint>
#include <string>
#include <vector>

namespace yv {

/// What a picture's renders report beside the picture, each renderer the
/// fields it knows (the others stay 0).
struct RenderReport {
    RgbImage image;
    std::string renderer;        ///< the GL renderer's name (empty for a cut)
    int level = 0;               ///< 0: full resolution; L: means of 2^L voxels a side
    bool storedLevel = false;    ///< a coarse level read from the file's density_lodL grids, not reduced from level 0
    std::uint64_t fineBricks = 0, levelBricks = 0, gpuBytes = 0, proxyTriangles = 0;
    /// Slices drawn (slices: the garment's, those in view; texture-slicing
    /// and half-angle: planes) and splats drawn (splatting).
    std::uint64_t slices = 0, splats = 0;
    std::uint64_t garmentSlices = 0; ///< slices: all the garment's, drawn or not
    std::string slicePrimitive;      ///< slices: how the last frame drew its slabs, "tiles", "points" or "boxes"
    std::uint64_t budgetBytes = 0; ///< the budget the level was chosen for
    double meanSamples = 0.0, loadSeconds = 0.0;
    double frameSeconds = 0.0, bestFrameSeconds = 0.0; ///< median and fastest of the repeated frames
    /// The work before each frame's draw (Renderer::prepare): for slices,
    /// the back-to-front sort, on the GPU, to its end (their frame time is
    /// the draw alone).
    double sortSeconds = 0.0, bestSortSeconds = 0.0;
};

/// One frame as a renderer draws it: from `camera`, into `target`.
struct Frame {
    const Camera& camera;
    const RenderTarget& target; ///< bound, its viewport set and cleared to zero when draw() is called
};

class Renderer {
  public:
    virtual ~Renderer() = default;

    /// The formats of the frame's colour textures; the first holds the picture.
    virtual std::vector<GLenum> targetFormats() const = 0;
    /// What a frame needs before its draw that its time leaves out (the
    /// slices' back-to-front sort, reported apart; per-camera geometry and
    /// scratch targets). drawFrames calls it before every draw().
    virtual void prepare(const Camera&) {}
    /// Draws one frame into `frame.target`. It may bind other targets of its
    /// own but leaves the frame's bound when it returns.
    virtual void draw(const Frame& frame) = 0;
    /// Starts reading the picture of the frame drawn last, without waiting
    /// for the draw: by default the first texture's RGB, over black. A
    /// renderer that makes its picture on the host reads it here, whole.
    virtual PendingRgbImage startPicture(const Frame& frame);
    /// The picture of the frame drawn last (startPicture's, waited for).
    RgbImage picture(const Frame& frame) { return startPicture(frame).finish(); }
    /// Adds what the renderer counted (slices, splats, samples) to `report`.
    virtual void describe(RenderReport&) const {}

    // What a live view changes between frames without making the renderer
    // again; a renderer that draws without it ignores it.
    /// The transfer function of the next frames (ray casts, slicing, splats).
    virtual void setTransferFunction(const TransferFunction&) {}
    /// The yarn twist the next frames shade with, radians per voxel of yarn (slices).
    virtual void setTwist(double) {}
    /// The level of detail of the next frames, in pixels (slices: SliceSettings::lodPixels).
    virtual void setSliceLod(double) {}
};

/// Draws `repeat` frames (at least one, the same picture each time) from
/// `camera`, and fills the report's picture, its frame and sort times
/// (median and fastest) and what the renderer counted. Throws yv::Error on
/// a GL error or a target the driver refuses.
void drawFrames(Renderer& renderer, const Camera& camera, int repeat, RenderReport& report);

/// One picture drawn without waiting for the GPU, as drawFrames draws one
/// frame: the order made (prepare) and the draw queued, each with its GPU
/// time measured (timer queries on a GPU; on llvmpipe, whose queries answer
/// garbage, glFinish at both ends), and its picture's read-back started.
/// finish() waits for it. The live view queues its two halves so, then
/// reads both: the GPU draws the second while the host takes the first.
class PictureInFlight {
  public:
    /// `timerQueries`: GlInfo::hardware().
    PictureInFlight(Renderer& renderer, const Camera& camera, bool timerQueries);
    PictureInFlight(const PictureInFlight&) = delete;
    PictureInFlight& operator=(const PictureInFlight&) = delete;
    /// The report drawFrames gives for one frame (sortSeconds and
    /// frameSeconds: the prepare's and the draw's GPU time).
    RenderReport finish();

  private:
    Renderer& renderer_;
    RenderTarget target_;
    GpuTimer prepareTimer_, timer_; ///< the prepare's and the draw's GPU time
    PendingRgbImage picture_;
};

} // namespace yv

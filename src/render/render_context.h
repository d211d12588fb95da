// The GL context of one `yarnvox inspect` command. The command makes one and
// lends it to whatever draws: every picture of the command (an HTML report
// draws many) shares the context, and no renderer makes its own. The EGL
// context itself is only created when the first picture needs it, so a cut,
// a report of an empty volume, or a request refused for its input runs where
// no GL is. The bricks its pictures load stay on the GPU for the next
// picture of the same volume (render/brick_cache.h).
#pragma once

#include "gpu/egl_context.h"
#include "render/brick_cache.h"

#include <optional>

namespace yv {

class RenderContext {
  public:
    /// `device`: the EGL device index (-1: the first GPU, else llvmpipe).
    explicit RenderContext(int device = -1) : device_(device) {}

    /// The context, made current on the calling thread; made on the first
    /// call. Throws yv::Error (one line saying what to install) where none
    /// can be had.
    GlContext& gl() {
        if (context_) context_->makeCurrent();
        else context_.emplace(GlContextOptions{device_, false});
        return *context_;
    }

    /// The atlases this command's pictures share.
    BrickCache& bricks() { return bricks_; }

  private:
    int device_;
    std::optional<GlContext> context_;
    BrickCache bricks_; ///< after the context: its textures go first
};

} // namespace yv

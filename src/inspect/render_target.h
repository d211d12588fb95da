// Off-screen GL targets of inspect's renders (ray casting, slicing, splatting), and
// reading one back as a picture (the context must be current).
#pragma once

#include "inspect/png_image.h"

#include <epoxy/gl.h>

#include <initializer_list>
#include <vector>

namespace yv {

/// A framebuffer with one colour texture per given format, deleted with it.
struct RenderTarget {
    GLuint fbo = 0;
    std::vector<GLuint> textures;
    /// Throws yv::Error when the driver does not complete the framebuffer.
    RenderTarget(int width, int height, std::initializer_list<GLenum> formats);
    ~RenderTarget();
    RenderTarget(const RenderTarget&) = delete;
    RenderTarget& operator=(const RenderTarget&) = delete;
};

/// The RGB of an RGBA8 texture, rows top first (GL's run bottom to top).
RgbImage readRgbImage(GLuint texture, int width, int height);

} // namespace yv

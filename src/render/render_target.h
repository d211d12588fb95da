// Off-screen GL targets the renders draw into (the picture's frame, a ray
// caster's entry distances, the half-angle light buffer), and reading one
// back (the context must be current).
#pragma once

#include "gpu/gl_objects.h"
#include "inspect/png_image.h"

#include <epoxy/gl.h>

#include <utility>
#include <vector>

namespace yv {

/// A framebuffer with one colour texture per given format (linear
/// filtering, clamped at the edges), all deleted with it.
class RenderTarget {
  public:
    /// Throws yv::Error when the driver does not complete the framebuffer.
    RenderTarget(int width, int height, const std::vector<GLenum>& formats);

    int width() const { return width_; }
    int height() const { return height_; }
    GLuint framebuffer() const { return framebuffer_.id(); }
    GLuint texture(std::size_t attachment) const { return textures_[attachment].id(); }

    /// Binds it for drawing, the viewport its size.
    void bind() const;
    /// Sets every colour texture to `rgba`.
    void clear(const float rgba[4]) const;

  private:
    int width_, height_;
    GlFramebuffer framebuffer_;
    std::vector<GlTexture> textures_;
};

/// A picture's colour on its way back to the host: the copy is queued
/// behind the GL commands so far (the draw need not have finished) into a
/// pixel-pack buffer the host maps, and finish() waits for it. Or an image
/// already read (a renderer that makes its picture on the host).
class PendingRgbImage {
  public:
    PendingRgbImage() = default;
    explicit PendingRgbImage(RgbImage done) : done_(std::move(done)), ready_(true) {}
    /// Starts reading the RGB of an RGBA texture.
    static PendingRgbImage start(GLuint texture, int width, int height);
    /// The image, rows top first (GL's run bottom to top); waits for the copy.
    RgbImage finish();

  private:
    GlBufferName pack_;
    int width_ = 0, height_ = 0;
    RgbImage done_;
    bool ready_ = false;
};

/// The RGB of an RGBA texture, as unsigned bytes, rows top first (GL's run
/// bottom to top).
RgbImage readRgbImage(GLuint texture, int width, int height);

/// The red channel of a float texture, rows top first.
std::vector<float> readRedFloats(GLuint texture, int width, int height);

} // namespace yv

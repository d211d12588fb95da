#include "render/render_target.h"

#include "core/error.h"
#include "gpu/gl_program.h"

#include <algorithm>
#include <cstdint>

namespace yv {

RenderTarget::RenderTarget(int width, int height, const std::vector<GLenum>& formats)
    : width_(width), height_(height), framebuffer_(createFramebuffer()) {
    GLenum attachment = GL_COLOR_ATTACHMENT0;
    std::vector<GLenum> drawBuffers;
    for (const GLenum format : formats) {
        GlTexture t = createTexture(GL_TEXTURE_2D);
        glTextureStorage2D(t.id(), 1, format, width, height);
        glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(t.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(t.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glNamedFramebufferTexture(framebuffer_.id(), attachment, t.id(), 0);
        drawBuffers.push_back(attachment++);
        textures_.push_back(std::move(t));
    }
    glNamedFramebufferDrawBuffers(framebuffer_.id(), GLsizei(drawBuffers.size()), drawBuffers.data());
    if (glCheckNamedFramebufferStatus(framebuffer_.id(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Error("the render target is not complete (image size too large for the driver?)");
}

void RenderTarget::bind() const {
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
    glViewport(0, 0, width_, height_);
}

void RenderTarget::clear(const float rgba[4]) const {
    for (std::size_t i = 0; i < textures_.size(); ++i) glClearNamedFramebufferfv(framebuffer_.id(), GL_COLOR, GLint(i), rgba);
}

PendingRgbImage PendingRgbImage::start(GLuint texture, int width, int height) {
    // Through a pixel-pack buffer the host maps rather than straight into
    // host memory: the live view reads a picture or two every frame, and on
    // the H200 a read took 4.0 ms where it now takes 1.6 to 1.9 (640x720,
    // the ray cast's samples no longer read beside it).
    PendingRgbImage p;
    p.width_ = width, p.height_ = height;
    const std::size_t bytes = std::size_t(width) * std::size_t(height) * 4u;
    GLuint id = 0;
    glCreateBuffers(1, &id);
    p.pack_.reset(id);
    glNamedBufferStorage(id, GLsizeiptr(std::max<std::size_t>(bytes, 4)), nullptr, GL_MAP_READ_BIT | GL_CLIENT_STORAGE_BIT);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, id);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(texture, 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(bytes), nullptr);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glFlush(); // under way while the host goes on
    checkGlError("reading the render back");
    return p;
}

RgbImage PendingRgbImage::finish() {
    if (ready_) return std::move(done_);
    const std::size_t w = std::size_t(width_), h = std::size_t(height_), bytes = w * h * 4u;
    RgbImage image(width_, height_);
    if (bytes > 0) {
        // Mapping waits for the copy.
        const auto* rgba = static_cast<const std::uint8_t*>(glMapNamedBufferRange(pack_.id(), 0, GLsizeiptr(bytes), GL_MAP_READ_BIT));
        if (!rgba) throw Error("reading the render back: the driver did not map the picture's buffer");
        // Rows bottom first in GL, top first in the image; RGBA to RGB.
        for (std::size_t y = 0; y < h; ++y) {
            const std::uint8_t* from = rgba + (h - 1 - y) * w * 4u;
            std::uint8_t* to = image.at(0, int(y));
            for (std::size_t x = 0; x < w; ++x) to[3 * x] = from[4 * x], to[3 * x + 1] = from[4 * x + 1], to[3 * x + 2] = from[4 * x + 2];
        }
        glUnmapNamedBuffer(pack_.id());
    }
    pack_.reset();
    ready_ = true;
    return image;
}

RgbImage readRgbImage(GLuint texture, int width, int height) { return PendingRgbImage::start(texture, width, height).finish(); }

std::vector<float> readRedFloats(GLuint texture, int width, int height) {
    const std::size_t w = std::size_t(width), h = std::size_t(height);
    std::vector<float> bottomUp(w * h), rows(w * h);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTextureImage(texture, 0, GL_RED, GL_FLOAT, GLsizei(bottomUp.size() * sizeof(float)), bottomUp.data());
    checkGlError("reading the render back");
    for (std::size_t y = 0; y < h; ++y) std::copy_n(&bottomUp[(h - 1 - y) * w], w, &rows[y * w]);
    return rows;
}

} // namespace yv

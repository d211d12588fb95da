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

RgbImage readRgbImage(GLuint texture, int width, int height) {
    std::vector<std::uint8_t> rgba(std::size_t(width) * std::size_t(height) * 4u);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(texture, 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(rgba.size()), rgba.data());
    checkGlError("reading the render back");
    RgbImage image(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            std::copy_n(&rgba[(std::size_t(height - 1 - y) * std::size_t(width) + std::size_t(x)) * 4], 3, image.at(x, y));
    return image;
}

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

#include "inspect/render_target.h"

#include "core/error.h"
#include "gpu/gl_program.h"

#include <algorithm>
#include <cstdint>

namespace yv {

RenderTarget::RenderTarget(int width, int height, std::initializer_list<GLenum> formats) {
    glCreateFramebuffers(1, &fbo);
    GLenum attachment = GL_COLOR_ATTACHMENT0;
    std::vector<GLenum> drawBuffers;
    for (GLenum f : formats) {
        GLuint t = 0;
        glCreateTextures(GL_TEXTURE_2D, 1, &t);
        glTextureStorage2D(t, 1, f, width, height);
        glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(t, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(t, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glNamedFramebufferTexture(fbo, attachment, t, 0);
        drawBuffers.push_back(attachment++);
        textures.push_back(t);
    }
    glNamedFramebufferDrawBuffers(fbo, GLsizei(drawBuffers.size()), drawBuffers.data());
    if (glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Error("the render target is not complete (image size too large for the driver?)");
}

RenderTarget::~RenderTarget() {
    glDeleteFramebuffers(1, &fbo);
    glDeleteTextures(GLsizei(textures.size()), textures.data());
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

} // namespace yv

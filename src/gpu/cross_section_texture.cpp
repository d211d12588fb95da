#include "gpu/cross_section_texture.h"

#include "core/error.h"
#include "gpu/gl_program.h"

namespace yv {

GLuint uploadCrossSectionTexture(const CrossSection& xs) {
    GLuint texture = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &texture);
    glTextureStorage2D(texture, 1, GL_R8UI, xs.size, xs.size);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(texture, 0, 0, 0, xs.size, xs.size, GL_RED_INTEGER, GL_UNSIGNED_BYTE, xs.density.data());
    glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureParameteri(texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    checkGlError("uploading the cross-section");
    return texture;
}

GLuint uploadAlbedoTexture(const CrossSection& xs) {
    YV_CHECK(xs.albedo.size() == std::size_t(xs.size) * xs.size);
    GLuint texture = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &texture);
    glTextureStorage2D(texture, 1, GL_RGB32F, xs.size, xs.size);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(texture, 0, 0, 0, xs.size, xs.size, GL_RGB, GL_FLOAT, xs.albedo.data());
    glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureParameteri(texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    checkGlError("uploading the cross-section's colour");
    return texture;
}

std::vector<std::string> crossSectionDefines(const CrossSection& xs, TexelReads reads, const std::string& platform) {
    const bool gather = reads == TexelReads::Gather || (reads == TexelReads::Auto && platform == "surfaceless");
    return {std::string("CROSS_SECTION_DISK ") + (xs.analyticDisk ? "1" : "0"),
            std::string("CROSS_SECTION_GATHER ") + (gather ? "1" : "0")};
}

} // namespace yv

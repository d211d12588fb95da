#include "gpu/cross_section_texture.h"

#include "core/error.h"
#include "gpu/gl_program.h"

namespace yv {

namespace {

/// A square texture of `size` texels read exactly (nearest, clamped to the
/// edge, as the CPU reads the cross-section).
GLuint uploadExactTexture(int size, GLenum storage, GLenum format, GLenum type, const void* texels, const char* what) {
    GLuint texture = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &texture);
    glTextureStorage2D(texture, 1, storage, size, size);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(texture, 0, 0, 0, size, size, format, type, texels);
    glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureParameteri(texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    checkGlError(what);
    return texture;
}

} // namespace

GLuint uploadCrossSectionTexture(const CrossSection& xs) {
    return uploadExactTexture(xs.size, GL_R8UI, GL_RED_INTEGER, GL_UNSIGNED_BYTE, xs.density.data(),
                              "uploading the cross-section");
}

GLuint uploadAlbedoTexture(const CrossSection& xs) {
    YV_CHECK(xs.albedo.size() == std::size_t(xs.size) * xs.size);
    return uploadExactTexture(xs.size, GL_RGB32F, GL_RGB, GL_FLOAT, xs.albedo.data(),
                              "uploading the cross-section's colour");
}

std::vector<std::string> crossSectionDefines(const CrossSection& xs, TexelReads reads, const std::string& platform) {
    const bool gather = reads == TexelReads::Gather || (reads == TexelReads::Auto && platform == "surfaceless");
    return {std::string("CROSS_SECTION_DISK ") + (xs.analyticDisk ? "1" : "0"),
            std::string("CROSS_SECTION_GATHER ") + (gather ? "1" : "0")};
}

} // namespace yv

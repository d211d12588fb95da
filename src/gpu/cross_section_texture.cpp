#include "gpu/cross_section_texture.h"

#include "core/error.h"
#include "gpu/gl_program.h"

#include <algorithm>
#include <cstdint>

namespace yv {

namespace {

/// A square texture of `size` texels read exactly (nearest, clamped to the
/// edge, as the CPU reads the cross-section).
GlTexture uploadExactTexture(int size, GLenum storage, GLenum format, GLenum type, const void* texels, const char* what) {
    GlTexture texture = createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(texture.id(), 1, storage, size, size);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(texture.id(), 0, 0, 0, size, size, format, type, texels);
    glTextureParameteri(texture.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(texture.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureParameteri(texture.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(texture.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    checkGlError(what);
    return texture;
}

} // namespace

TexelReads texelReadsFor(TexelReads reads) { return reads == TexelReads::Auto ? TexelReads::Quad : reads; }

GlTexture uploadCrossSectionTexture(const CrossSection& xs, TexelReads reads) {
    YV_CHECK(reads != TexelReads::Auto && xs.density.size() == std::size_t(xs.size) * xs.size);
    if (reads != TexelReads::Quad)
        return uploadExactTexture(xs.size, GL_R8UI, GL_RED_INTEGER, GL_UNSIGNED_BYTE, xs.density.data(),
                                  "uploading the cross-section");
    // One texel per lookup corner floor(f) + 1 in [0, size] (common.glsl:
    // footprintDensity), holding what four clamped fetches would read.
    const int n = xs.size, side = n + 1;
    const auto at = [&](int x, int y) { return xs.density[std::size_t(std::clamp(y, 0, n - 1)) * n + std::clamp(x, 0, n - 1)]; };
    std::vector<std::uint8_t> quads(std::size_t(side) * side * 4);
    for (int v = 0; v < side; ++v)
        for (int u = 0; u < side; ++u) {
            std::uint8_t* q = &quads[(std::size_t(v) * side + u) * 4];
            q[0] = at(u - 1, v - 1);
            q[1] = at(u, v - 1);
            q[2] = at(u - 1, v);
            q[3] = at(u, v);
        }
    return uploadExactTexture(side, GL_RGBA8UI, GL_RGBA_INTEGER, GL_UNSIGNED_BYTE, quads.data(),
                              "uploading the cross-section");
}

GlTexture uploadAlbedoTexture(const CrossSection& xs) {
    YV_CHECK(xs.albedo.size() == std::size_t(xs.size) * xs.size);
    return uploadExactTexture(xs.size, GL_RGB32F, GL_RGB, GL_FLOAT, xs.albedo.data(),
                              "uploading the cross-section's colour");
}

std::vector<std::string> crossSectionDefines(const CrossSection& xs, TexelReads reads) {
    YV_CHECK(reads != TexelReads::Auto);
    return {std::string("CROSS_SECTION_DISK ") + (xs.analyticDisk ? "1" : "0"),
            std::string("CROSS_SECTION_GATHER ") + (reads == TexelReads::Gather ? "1" : "0"),
            std::string("CROSS_SECTION_QUAD ") + (reads == TexelReads::Quad ? "1" : "0")};
}

} // namespace yv

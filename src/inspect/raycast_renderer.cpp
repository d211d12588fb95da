#include "inspect/raycast_renderer.h"

#include "core/error.h"
#include "gpu/gl_program.h"
#include "inspect/proxy_geometry.h"
#include "inspect/render_target.h"

#include <glm/common.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace yv {

struct RaycastRenderer::Impl {
    const BrickAtlas& atlas;
    RenderMode mode;
    GlProgram proxy, march;
    GLuint vao = 0, proxyBuffer = 0, emptyVao = 0, tfTexture = 0;
    GLsizei proxyVertices = 0;

    Impl(const BrickAtlas& a, RenderMode m) : atlas(a), mode(m) {
        proxy = GlProgram::graphics("inspect_proxy.vert", "inspect_proxy.frag");
        std::vector<std::string> defines;
        if (m == RenderMode::Mip) defines.push_back("MIP");
        if (m == RenderMode::Orientation) defines.push_back("ORIENTATION");
        march = GlProgram::graphics("inspect_fullscreen.vert",
                                    m == RenderMode::Isosurface ? "inspect_isosurface.frag" : "inspect_raycast.frag", defines);

        const std::vector<glm::vec3> triangles = proxyTriangles(a.plan());
        proxyVertices = GLsizei(triangles.size());
        glCreateBuffers(1, &proxyBuffer);
        glNamedBufferStorage(proxyBuffer, GLsizeiptr(std::max<std::size_t>(triangles.size(), 1) * sizeof(glm::vec3)),
                             triangles.empty() ? nullptr : triangles.data(), 0);
        glCreateVertexArrays(1, &vao);
        glVertexArrayVertexBuffer(vao, 0, proxyBuffer, 0, sizeof(glm::vec3));
        glEnableVertexArrayAttrib(vao, 0);
        glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribBinding(vao, 0, 0);
        glCreateVertexArrays(1, &emptyVao);
        glCreateTextures(GL_TEXTURE_1D, 1, &tfTexture);
        glTextureStorage1D(tfTexture, 1, GL_RGBA32F, 256);
        glTextureParameteri(tfTexture, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(tfTexture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(tfTexture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        checkGlError("setting up the ray caster");
    }
    ~Impl() {
        glDeleteBuffers(1, &proxyBuffer);
        glDeleteVertexArrays(1, &vao);
        glDeleteVertexArrays(1, &emptyVao);
        glDeleteTextures(1, &tfTexture);
    }
};

RaycastRenderer::RaycastRenderer(const BrickAtlas& atlas, RenderMode mode) : impl_(std::make_unique<Impl>(atlas, mode)) {}
RaycastRenderer::~RaycastRenderer() = default;

RaycastResult RaycastRenderer::render(const Camera& camera, const RaycastSettings& s) {
    Impl& m = *impl_;
    const int w = camera.width, h = camera.height;
    const LevelPlan& plan = m.atlas.plan();
    const glm::mat4 vp(camera.viewProjection());
    const glm::mat4 inv(glm::inverse(camera.viewProjection()));
    const glm::vec2 viewport{float(w), float(h)};
    glTextureSubImage1D(m.tfTexture, 0, 0, 256, GL_RGBA, GL_FLOAT, s.transferFunction.data());

    RenderTarget entry(w, h, {GL_RG32F});
    RenderTarget out(w, h, {GL_RGBA8, GL_R32F});
    glFinish();
    const auto start = std::chrono::steady_clock::now();
    glViewport(0, 0, w, h);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    if (s.skipEmpty) {
        glBindFramebuffer(GL_FRAMEBUFFER, entry.fbo);
        const float far[4] = {3.0e38f, 3.0e38f, 0.0f, 0.0f};
        glClearNamedFramebufferfv(entry.fbo, GL_COLOR, 0, far);
        glEnable(GL_BLEND);
        glBlendEquation(GL_MIN);
        m.proxy.use();
        glUniformMatrix4fv(m.proxy.uniform("viewProjection"), 1, GL_FALSE, glm::value_ptr(vp));
        glUniformMatrix4fv(m.proxy.uniform("inverseViewProjection"), 1, GL_FALSE, glm::value_ptr(inv));
        glUniform2fv(m.proxy.uniform("viewport"), 1, glm::value_ptr(viewport));
        glBindVertexArray(m.vao);
        glDrawArrays(GL_TRIANGLES, 0, m.proxyVertices);
        glDisable(GL_BLEND);
        glBlendEquation(GL_FUNC_ADD);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, out.fbo);
    m.march.use();
    const GlProgram& p = m.march;
    glUniformMatrix4fv(p.uniform("inverseViewProjection"), 1, GL_FALSE, glm::value_ptr(inv));
    glUniform2fv(p.uniform("viewport"), 1, glm::value_ptr(viewport));
    glUniform1i(p.uniform("skipEmpty"), s.skipEmpty ? 1 : 0);
    const glm::dvec3 eye = camera.eye;
    const glm::dvec3 boxMin(plan.originVoxel), boxMax(glm::dvec3(plan.originVoxel) + glm::dvec3(plan.brickDims * (kBrickSize * plan.scale)));
    const bool eyeInBox = glm::all(glm::greaterThanEqual(eye, boxMin)) && glm::all(glm::lessThanEqual(eye, boxMax));
    glUniform1i(p.uniform("startAtNearPlane"), eyeInBox ? 1 : 0);
    const glm::ivec3 slots = m.atlas.slotsPerAxis();
    glUniform3i(p.uniform("atlasSlots"), slots.x, slots.y, slots.z);
    glUniform3f(p.uniform("originVoxel"), float(plan.originVoxel.x), float(plan.originVoxel.y), float(plan.originVoxel.z));
    glUniform1f(p.uniform("levelScale"), float(plan.scale));
    glUniform3i(p.uniform("brickDims"), plan.brickDims.x, plan.brickDims.y, plan.brickDims.z);
    glUniform3f(p.uniform("boxMin"), float(boxMin.x), float(boxMin.y), float(boxMin.z));
    glUniform3f(p.uniform("boxMax"), float(boxMax.x), float(boxMax.y), float(boxMax.z));
    glUniform1f(p.uniform("step"), float(s.stepVoxels * plan.scale));
    glUniform1f(p.uniform("densityScale"), 1.0f);
    glUniform1f(p.uniform("isoValue"), float(s.isoValue));
    // The isosurface's light: above the eye and behind it, so the side facing
    // the camera's up is lit and the one below it is in shade.
    const glm::dmat4 toWorld = glm::inverse(camera.view);
    const glm::vec3 light(glm::normalize(glm::dvec3(toWorld[1]) + glm::dvec3(toWorld[2])));
    glUniform3fv(p.uniform("lightDirection"), 1, glm::value_ptr(light));
    glBindTextureUnit(0, entry.textures[0]);
    glBindTextureUnit(1, m.atlas.indirectionTexture());
    glBindTextureUnit(2, m.atlas.densityTexture());
    glBindTextureUnit(3, m.atlas.orientationTexture() ? m.atlas.orientationTexture() : m.atlas.densityTexture());
    glBindTextureUnit(4, m.tfTexture);
    glBindVertexArray(m.emptyVao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glFinish();
    RaycastResult r;
    r.frameSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.proxyTriangles = std::uint64_t(m.proxyVertices / 3);
    checkGlError("ray casting");

    std::vector<std::uint8_t> rgba(std::size_t(w) * std::size_t(h) * 4u);
    std::vector<float> samples(std::size_t(w) * std::size_t(h));
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(out.textures[0], 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(rgba.size()), rgba.data());
    glGetTextureImage(out.textures[1], 0, GL_RED, GL_FLOAT, GLsizei(samples.size() * sizeof(float)), samples.data());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    checkGlError("reading the render back");
    // GL's rows run bottom to top; images run top to bottom.
    r.image = RgbImage(w, h);
    r.samples.resize(samples.size());
    double total = 0.0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t from = std::size_t(h - 1 - y) * std::size_t(w) + std::size_t(x);
            std::copy_n(&rgba[from * 4], 3, r.image.at(x, y));
            r.samples[std::size_t(y) * std::size_t(w) + std::size_t(x)] = samples[from];
            total += samples[from];
        }
    r.meanSamples = total / double(std::max(1, w * h));
    return r;
}

RgbImage samplesImage(const std::vector<float>& samples, int width, int height, float maxSamples) {
    RgbImage image(width, height);
    const glm::vec3 ramp[] = {{0.0f, 0.0f, 0.6f}, {0.9f, 0.1f, 0.1f}, {1.0f, 1.0f, 0.2f}};
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const float n = samples[std::size_t(y) * std::size_t(width) + std::size_t(x)];
            if (n <= 0.0f) continue;
            const float t = std::clamp(n / std::max(maxSamples, 1.0f), 0.0f, 1.0f) * 2.0f;
            const int i = std::min(int(t), 1);
            const glm::vec3 c = glm::mix(ramp[i], ramp[i + 1], t - float(i));
            std::uint8_t* p = image.at(x, y);
            for (int k = 0; k < 3; ++k) p[k] = std::uint8_t(std::lround(255.0f * c[k]));
        }
    return image;
}

} // namespace yv

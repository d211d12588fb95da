#include "render/raycast_renderer.h"

#include "core/error.h"
#include "inspect/proxy_geometry.h"

#include <glm/common.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>

namespace yv {
namespace {

GlProgram marchProgram(RenderMode mode) {
    std::vector<std::string> defines;
    if (mode == RenderMode::Mip) defines.push_back("MIP");
    if (mode == RenderMode::Orientation) defines.push_back("ORIENTATION");
    return GlProgram::graphics("inspect_fullscreen.vert",
                               mode == RenderMode::Isosurface ? "inspect_isosurface.frag" : "inspect_raycast.frag", defines);
}

} // namespace

RaycastRenderer::RaycastRenderer(const BrickAtlas& atlas, RenderMode mode, const RaycastSettings& settings)
    : atlas_(atlas), settings_(settings), proxy_(GlProgram::graphics("inspect_proxy.vert", "inspect_proxy.frag")),
      march_(marchProgram(mode)), proxyArray_(createVertexArray()), emptyArray_(createVertexArray()),
      transferFunction_(settings.transferFunction) {
    const std::vector<glm::vec3> triangles = yv::proxyTriangles(atlas.plan());
    proxyVertices_ = GLsizei(triangles.size());
    proxyBuffer_.upload(triangles.data(), triangles.size() * sizeof(glm::vec3), nullptr);
    const GLuint vao = proxyArray_.id();
    glVertexArrayVertexBuffer(vao, 0, proxyBuffer_.id(), 0, sizeof(glm::vec3));
    glEnableVertexArrayAttrib(vao, 0);
    glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao, 0, 0);
    checkGlError("setting up the ray caster");
}

/// The first pass: the nearest entry and farthest exit of the occupied
/// bricks' boundary per pixel (GL_MIN of entry and of minus exit).
void RaycastRenderer::drawEntryDistances(const Camera& camera) {
    entry_->bind();
    const float far[4] = {3.0e38f, 3.0e38f, 0.0f, 0.0f};
    entry_->clear(far);
    glEnable(GL_BLEND);
    glBlendEquation(GL_MIN);
    proxy_.use();
    const glm::mat4 vp(camera.viewProjection());
    const glm::mat4 inv(glm::inverse(camera.viewProjection()));
    const glm::vec2 viewport{float(camera.width), float(camera.height)};
    glUniformMatrix4fv(proxy_.uniform("viewProjection"), 1, GL_FALSE, glm::value_ptr(vp));
    glUniformMatrix4fv(proxy_.uniform("inverseViewProjection"), 1, GL_FALSE, glm::value_ptr(inv));
    glUniform2fv(proxy_.uniform("viewport"), 1, glm::value_ptr(viewport));
    glBindVertexArray(proxyArray_.id());
    glDrawArrays(GL_TRIANGLES, 0, proxyVertices_);
    glDisable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
}

void RaycastRenderer::setMarchUniforms(const Camera& camera) const {
    const LevelPlan& plan = atlas_.plan();
    const GlProgram& p = march_;
    const glm::mat4 inv(glm::inverse(camera.viewProjection()));
    const glm::vec2 viewport{float(camera.width), float(camera.height)};
    glUniformMatrix4fv(p.uniform("inverseViewProjection"), 1, GL_FALSE, glm::value_ptr(inv));
    glUniform2fv(p.uniform("viewport"), 1, glm::value_ptr(viewport));
    glUniform1i(p.uniform("skipEmpty"), settings_.skipEmpty ? 1 : 0);
    const glm::dvec3 eye = camera.eye;
    const glm::dvec3 boxMin(plan.originVoxel),
        boxMax(glm::dvec3(plan.originVoxel) + glm::dvec3(plan.brickDims * (kBrickSize * plan.scale)));
    const bool eyeInBox = glm::all(glm::greaterThanEqual(eye, boxMin)) && glm::all(glm::lessThanEqual(eye, boxMax));
    glUniform1i(p.uniform("startAtNearPlane"), eyeInBox ? 1 : 0);
    atlas_.setAddressingUniforms(p);
    glUniform3f(p.uniform("boxMin"), float(boxMin.x), float(boxMin.y), float(boxMin.z));
    glUniform3f(p.uniform("boxMax"), float(boxMax.x), float(boxMax.y), float(boxMax.z));
    glUniform1f(p.uniform("step"), float(settings_.stepVoxels * plan.scale));
    glUniform1f(p.uniform("densityScale"), 1.0f);
    glUniform1f(p.uniform("isoValue"), float(settings_.isoValue));
    // The isosurface's light: above the eye and behind it, so the side facing
    // the camera's up is lit and the one below it is in shade.
    const glm::dmat4 toWorld = glm::inverse(camera.view);
    const glm::vec3 light(glm::normalize(glm::dvec3(toWorld[1]) + glm::dvec3(toWorld[2])));
    glUniform3fv(p.uniform("lightDirection"), 1, glm::value_ptr(light));
}

void RaycastRenderer::prepare(const Camera& camera) {
    if (!entry_ || entry_->width() != camera.width || entry_->height() != camera.height)
        entry_.emplace(camera.width, camera.height, std::vector<GLenum>{GL_RG32F});
}

void RaycastRenderer::draw(const Frame& frame) {
    const Camera& camera = frame.camera;
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    if (settings_.skipEmpty) {
        drawEntryDistances(camera);
        frame.target.bind();
    }
    march_.use();
    setMarchUniforms(camera);
    glBindTextureUnit(0, entry_->texture(0));
    glBindTextureUnit(1, atlas_.indirectionTexture());
    glBindTextureUnit(2, atlas_.densityTexture());
    glBindTextureUnit(3, atlas_.orientationTexture() ? atlas_.orientationTexture() : atlas_.densityTexture());
    glBindTextureUnit(4, transferFunction_.id());
    glBindVertexArray(emptyArray_.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    checkGlError("ray casting");
}

PendingRgbImage RaycastRenderer::startPicture(const Frame& frame) {
    const int w = frame.target.width(), h = frame.target.height();
    if (!settings_.countSamples && !settings_.showSamples) return Renderer::startPicture(frame);
    samples_ = readRedFloats(frame.target.texture(1), w, h);
    double total = 0.0;
    for (const float n : samples_) total += n;
    meanSamples_ = total / double(std::max(1, w * h));
    if (!settings_.showSamples) return Renderer::startPicture(frame);
    const float most = samples_.empty() ? 1.0f : *std::max_element(samples_.begin(), samples_.end());
    return PendingRgbImage(samplesImage(samples_, w, h, most));
}

void RaycastRenderer::describe(RenderReport& report) const {
    report.proxyTriangles = settings_.skipEmpty ? proxyTriangles() : 0;
    report.meanSamples = meanSamples_;
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

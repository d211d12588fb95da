#include "render/slicing_renderer.h"

#include "core/error.h"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace yv {
namespace {

/// An orthographic view along -towardsLight that holds the sphere around `centre`.
glm::dmat4 lightViewProjection(const glm::dvec3& centre, double radius, const glm::dvec3& toLight) {
    const glm::dvec3 up = std::abs(toLight.z) > 0.999 ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1);
    const glm::dmat4 view = glm::lookAt(centre + 2.0 * radius * toLight, centre, up);
    return glm::ortho(-radius, radius, -radius, radius, 0.5 * radius, 3.5 * radius) * view;
}

/// The level's box in voxel coordinates.
std::pair<glm::dvec3, glm::dvec3> levelBox(const LevelPlan& plan) {
    const glm::dvec3 lo(plan.originVoxel);
    return {lo, lo + glm::dvec3(plan.brickDims * (kBrickSize * plan.scale))};
}

} // namespace

SlicingRenderer::SlicingRenderer(const BrickAtlas& atlas, SlicingMode mode, const SlicingSettings& settings)
    : atlas_(atlas), mode_(mode), settings_(settings),
      eyePass_(GlProgram::graphics("inspect_slice.vert", "inspect_slice.frag",
                                   mode == SlicingMode::HalfAngle ? std::vector<std::string>{"HALF_ANGLE"}
                                                                  : std::vector<std::string>{})),
      transferFunction_(settings.transferFunction) {
    if (mode == SlicingMode::HalfAngle) lightPass_ = GlProgram::graphics("inspect_slice.vert", "inspect_slice.frag", {"LIGHT_PASS"});
    checkGlError("setting up the slicing renderer");
}

void SlicingRenderer::prepare(const Camera& camera) {
    const auto [boxMin, boxMax] = levelBox(atlas_.plan());
    // The camera looks down its -z: that axis in voxel coordinates.
    const glm::dvec3 forward = -glm::normalize(glm::dvec3(camera.view[0][2], camera.view[1][2], camera.view[2][2]));
    const glm::dvec3 toLight = towardsLight(settings_.light);
    const glm::dvec3 lightTravel = -toLight;
    // Texture slicing: planes facing the eye, drawn farthest first. Half-angle:
    // planes facing the half vector, drawn nearest the light first; the eye
    // sees them front to back when the light is behind it, else back to front.
    normal_ = forward;
    frontToBack_ = false;
    if (mode_ == SlicingMode::HalfAngle) {
        frontToBack_ = glm::dot(forward, lightTravel) >= 0.0;
        normal_ = glm::normalize(frontToBack_ ? forward + lightTravel : lightTravel - forward);
    }
    const double depth = boxDepth(boxMin, boxMax, normal_);
    spacing_ = settings_.slices > 0 ? depth / double(settings_.slices) : double(atlas_.plan().scale);
    stack_ = sliceStack(boxMin, boxMax, normal_, spacing_);
    stackBuffer_.upload(stack_.triangles.data(), stack_.triangles.size() * sizeof(glm::vec3), nullptr);
    stackArray_ = createVertexArray();
    const GLuint vao = stackArray_.id();
    glVertexArrayVertexBuffer(vao, 0, stackBuffer_.id(), 0, sizeof(glm::vec3));
    glEnableVertexArrayAttrib(vao, 0);
    glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao, 0, 0);

    const glm::dvec3 centre = 0.5 * (boxMin + boxMax);
    lightMatrix_ = glm::mat4(lightViewProjection(centre, 0.5 * glm::length(boxMax - boxMin), toLight));
    const int lightSize = std::clamp(std::max(camera.width, camera.height), 64, 1024);
    if (mode_ == SlicingMode::HalfAngle && (!light_ || light_->width() != lightSize))
        light_.emplace(lightSize, lightSize, std::vector<GLenum>{GL_RGBA32F});
}

/// The uniforms both passes share: the atlas, the slices.
void SlicingRenderer::setVolumeUniforms(const GlProgram& p, const glm::mat4& viewProjection) const {
    p.use();
    glUniformMatrix4fv(p.uniform("viewProjection"), 1, GL_FALSE, glm::value_ptr(viewProjection));
    atlas_.setAddressingUniforms(p);
    glUniform3f(p.uniform("sliceNormal"), float(normal_.x), float(normal_.y), float(normal_.z));
    glUniform1f(p.uniform("spacing"), float(spacing_));
}

void SlicingRenderer::draw(const Frame& frame) {
    const Camera& camera = frame.camera;
    setVolumeUniforms(eyePass_, glm::mat4(camera.viewProjection()));
    glUniform3f(eyePass_.uniform("eye"), float(camera.eye.x), float(camera.eye.y), float(camera.eye.z));
    glUniform1i(eyePass_.uniform("rayFromEye"), 1);
    if (light_) {
        const glm::dvec3 lightTravel = -towardsLight(settings_.light);
        glUniformMatrix4fv(eyePass_.uniform("lightViewProjection"), 1, GL_FALSE, glm::value_ptr(lightMatrix_));
        glUniform1f(eyePass_.uniform("ambient"), float(settings_.ambient));
        setVolumeUniforms(lightPass_, lightMatrix_);
        glUniform3f(lightPass_.uniform("lightTravel"), float(lightTravel.x), float(lightTravel.y), float(lightTravel.z));
        glUniform1i(lightPass_.uniform("rayFromEye"), 0);
    }
    glBindTextureUnit(1, atlas_.indirectionTexture());
    glBindTextureUnit(2, atlas_.densityTexture());
    glBindTextureUnit(4, transferFunction_.id());
    if (light_) glBindTextureUnit(5, light_->texture(0));
    glBindVertexArray(stackArray_.id());
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    if (mode_ == SlicingMode::TextureSlicing) {
        // Premultiplied colour "over" what lies behind, farthest slice first.
        glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
        for (std::size_t k = stack_.first.size(); k-- > 0;) glDrawArrays(GL_TRIANGLES, stack_.first[k], stack_.count[k]);
    } else {
        drawHalfAngle(frame);
    }
    glDisable(GL_BLEND);
    checkGlError("slicing");
}

void SlicingRenderer::drawHalfAngle(const Frame& frame) const {
    const float clear[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    light_->clear(clear);
    // The half vector points away from the light, so increasing k is the
    // light's front to back; for the eye it is front to back only when
    // the light is behind the viewer.
    for (std::size_t k = 0; k < stack_.first.size(); ++k) {
        const GLint first = stack_.first[k];
        const GLsizei count = stack_.count[k];
        if (count == 0) continue;
        frame.target.bind();
        if (frontToBack_) glBlendFunc(GL_ONE_MINUS_DST_ALPHA, GL_ONE); // "under"
        else glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);              // "over"
        eyePass_.use();
        glDrawArrays(GL_TRIANGLES, first, count);
        // Opacity towards the light, front to back as the light sees it.
        light_->bind();
        glBlendFunc(GL_ONE_MINUS_DST_ALPHA, GL_ONE);
        lightPass_.use();
        glDrawArrays(GL_TRIANGLES, first, count);
    }
    frame.target.bind();
}

} // namespace yv

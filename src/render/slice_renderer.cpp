#include "render/slice_renderer.h"

#include "core/error.h"

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>

#include <algorithm>

namespace yv {
namespace {

/// Extinction times the yarn's radius: a ray through the axis keeps e^-4 (2 %).
constexpr float kOpacityTimesRadius = 2.0f;
const glm::vec3 kAlbedo(0.92f, 0.78f, 0.58f);

/// Refuses more slices than the driver's buffer textures hold (two texels each).
const SliceInstances& fitting(const SliceInstances& s) {
    GLint maxTexels = 0;
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
    if (s.records.size() > std::size_t(maxTexels))
        throw Error("--render slices: " + std::to_string(s.count()) + " slices exceed the driver's buffer textures (" +
                    std::to_string(maxTexels / 2) + " slices): draw a --region");
    return s;
}

} // namespace

SliceRenderer::SliceRenderer(const SliceInstances& slices)
    : slices_(fitting(slices)), program_(GlProgram::graphics("inspect_slices.vert", "inspect_slices.frag")),
      sliceTexture_(createTexture(GL_TEXTURE_BUFFER)), orderArray_(createVertexArray()) {
    const std::size_t records = std::max<std::size_t>(slices.records.size(), 2);
    sliceBuffer_.reserve(records * sizeof(glm::vec4), nullptr);
    if (!slices.records.empty())
        glNamedBufferSubData(sliceBuffer_.id(), 0, GLsizeiptr(slices.records.size() * sizeof(glm::vec4)), slices.records.data());
    glTextureBuffer(sliceTexture_.id(), GL_RGBA32F, sliceBuffer_.id());
    orderBuffer_.reserve(std::max<std::size_t>(slices.count(), 1) * sizeof(std::uint32_t), nullptr);
    const GLuint vao = orderArray_.id();
    glVertexArrayVertexBuffer(vao, 0, orderBuffer_.id(), 0, sizeof(std::uint32_t));
    glVertexArrayBindingDivisor(vao, 0, 1);
    glEnableVertexArrayAttrib(vao, 0);
    glVertexArrayAttribIFormat(vao, 0, 1, GL_UNSIGNED_INT, 0);
    glVertexArrayAttribBinding(vao, 0, 0);
    checkGlError("uploading the slices");
}

void SliceRenderer::prepare(const Camera& camera) { sortBackToFront(slices_, camera.eye, order_); }

void SliceRenderer::draw(const Frame& frame) {
    const Camera& camera = frame.camera;
    if (!order_.empty())
        glNamedBufferSubData(orderBuffer_.id(), 0, GLsizeiptr(order_.size() * sizeof(std::uint32_t)), order_.data());
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA); // premultiplied "over", back to front
    program_.use();
    const glm::mat4 vp(camera.viewProjection());
    glUniformMatrix4fv(program_.uniform("viewProjection"), 1, GL_FALSE, glm::value_ptr(vp));
    const glm::vec3 eye(camera.eye);
    glUniform3fv(program_.uniform("eye"), 1, glm::value_ptr(eye));
    // Parallel light from over the viewer's shoulder: the camera's up and back.
    const glm::dmat4 inverseView = glm::inverse(camera.view);
    const glm::vec3 light(glm::normalize(glm::dvec3(inverseView[2]) + 0.5 * glm::dvec3(inverseView[1])));
    glUniform3fv(program_.uniform("lightDirection"), 1, glm::value_ptr(light));
    glUniform3fv(program_.uniform("albedo"), 1, glm::value_ptr(kAlbedo));
    const float radius = slices_.count() ? slices_.records[1].w : 1.0f;
    glUniform1f(program_.uniform("opacityPerVoxel"), kOpacityTimesRadius / std::max(radius, 1e-6f));
    glBindTextureUnit(0, sliceTexture_.id());
    glBindVertexArray(orderArray_.id());
    glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 14, GLsizei(order_.size()));
    glDisable(GL_BLEND);
    checkGlError("drawing the slices");
}

} // namespace yv

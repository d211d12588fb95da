#include "inspect/slice_renderer.h"

#include "core/error.h"
#include "gpu/gl_program.h"

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <chrono>
#include <vector>

namespace yv {
namespace {

/// Extinction times the yarn's radius: a ray through the axis keeps e^-4 (2 %).
constexpr float kOpacityTimesRadius = 2.0f;
const glm::vec3 kAlbedo(0.92f, 0.78f, 0.58f);

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

} // namespace

struct SliceRenderer::Impl {
    const SliceInstances& slices;
    GlProgram program;
    GLuint sliceBuffer = 0, sliceTexture = 0, orderBuffer = 0, vao = 0;
    std::vector<std::uint32_t> order;

    explicit Impl(const SliceInstances& s) : slices(s) {
        GLint maxTexels = 0;
        glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
        if (s.records.size() > std::size_t(maxTexels))
            throw Error("--render slices: " + std::to_string(s.count()) + " slices exceed the driver's buffer textures (" +
                        std::to_string(maxTexels / 2) + " slices): draw a --region");
        program = GlProgram::graphics("inspect_slices.vert", "inspect_slices.frag");
        const std::size_t n = std::max<std::size_t>(s.count(), 1);
        glCreateBuffers(1, &sliceBuffer);
        glNamedBufferStorage(sliceBuffer, GLsizeiptr(std::max<std::size_t>(s.records.size(), 2) * sizeof(glm::vec4)),
                             s.records.empty() ? nullptr : s.records.data(), 0);
        glCreateTextures(GL_TEXTURE_BUFFER, 1, &sliceTexture);
        glTextureBuffer(sliceTexture, GL_RGBA32F, sliceBuffer);
        glCreateBuffers(1, &orderBuffer);
        glNamedBufferStorage(orderBuffer, GLsizeiptr(n * sizeof(std::uint32_t)), nullptr, GL_DYNAMIC_STORAGE_BIT);
        glCreateVertexArrays(1, &vao);
        glVertexArrayVertexBuffer(vao, 0, orderBuffer, 0, sizeof(std::uint32_t));
        glVertexArrayBindingDivisor(vao, 0, 1);
        glEnableVertexArrayAttrib(vao, 0);
        glVertexArrayAttribIFormat(vao, 0, 1, GL_UNSIGNED_INT, 0);
        glVertexArrayAttribBinding(vao, 0, 0);
        checkGlError("uploading the slices");
    }
    ~Impl() {
        glDeleteVertexArrays(1, &vao);
        glDeleteTextures(1, &sliceTexture);
        glDeleteBuffers(1, &orderBuffer);
        glDeleteBuffers(1, &sliceBuffer);
    }
};

SliceRenderer::SliceRenderer(const SliceInstances& slices) : impl_(std::make_unique<Impl>(slices)) {}
SliceRenderer::~SliceRenderer() = default;

SliceFrame SliceRenderer::render(const Camera& camera) {
    Impl& m = *impl_;
    const int w = camera.width, h = camera.height;
    SliceFrame frame;
    auto start = std::chrono::steady_clock::now();
    sortBackToFront(m.slices, camera.eye, m.order);
    frame.sortSeconds = secondsSince(start);

    GLuint fbo = 0, target = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &target);
    glTextureStorage2D(target, 1, GL_RGBA8, w, h);
    glCreateFramebuffers(1, &fbo);
    glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, target, 0);
    const bool complete = glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    const auto release = [&] {
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glDeleteFramebuffers(1, &fbo);
        glDeleteTextures(1, &target);
    };
    if (!complete) {
        release();
        throw Error("the render target is not complete (image size too large for the driver?)");
    }
    const float black[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearNamedFramebufferfv(fbo, GL_COLOR, 0, black);
    glFinish();
    start = std::chrono::steady_clock::now();
    if (!m.order.empty())
        glNamedBufferSubData(m.orderBuffer, 0, GLsizeiptr(m.order.size() * sizeof(std::uint32_t)), m.order.data());
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, w, h);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA); // premultiplied "over", back to front
    m.program.use();
    const glm::mat4 vp(camera.viewProjection());
    glUniformMatrix4fv(m.program.uniform("viewProjection"), 1, GL_FALSE, glm::value_ptr(vp));
    const glm::vec3 eye(camera.eye);
    glUniform3fv(m.program.uniform("eye"), 1, glm::value_ptr(eye));
    // Parallel light from over the viewer's shoulder: the camera's up and back.
    const glm::dmat4 inverseView = glm::inverse(camera.view);
    const glm::vec3 light(glm::normalize(glm::dvec3(inverseView[2]) + 0.5 * glm::dvec3(inverseView[1])));
    glUniform3fv(m.program.uniform("lightDirection"), 1, glm::value_ptr(light));
    glUniform3fv(m.program.uniform("albedo"), 1, glm::value_ptr(kAlbedo));
    const float radius = m.slices.count() ? m.slices.records[1].w : 1.0f;
    glUniform1f(m.program.uniform("opacityPerVoxel"), kOpacityTimesRadius / std::max(radius, 1e-6f));
    glBindTextureUnit(0, m.sliceTexture);
    glBindVertexArray(m.vao);
    glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 14, GLsizei(m.order.size()));
    glFinish();
    frame.drawSeconds = secondsSince(start);
    glDisable(GL_BLEND);
    checkGlError("drawing the slices");

    std::vector<std::uint8_t> rgba(std::size_t(w) * std::size_t(h) * 4u);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(target, 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(rgba.size()), rgba.data());
    release();
    checkGlError("reading the slices back");
    // GL's rows run bottom to top; images run top to bottom.
    frame.image = RgbImage(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            std::copy_n(&rgba[(std::size_t(h - 1 - y) * std::size_t(w) + std::size_t(x)) * 4u], 3, frame.image.at(x, y));
    return frame;
}

} // namespace yv

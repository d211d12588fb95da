#include "inspect/slicing_renderer.h"

#include "core/error.h"
#include "core/text.h"
#include "gpu/gl_program.h"
#include "inspect/render_target.h"
#include "inspect/slice_stack.h"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace yv {

LightAngles parseLight(const std::string& text) {
    const std::optional<std::vector<double>> numbers = parseNumberList(text, 2);
    if (!numbers) throw Error("--light '" + text + "': expected azimuth,elevation (degrees, degrees)");
    LightAngles l{(*numbers)[0], (*numbers)[1]};
    if (l.elevation < -90.0 || l.elevation > 90.0) throw Error("--light '" + text + "': elevation must lie in [-90, 90] degrees");
    return l;
}

glm::dvec3 towardsLight(const LightAngles& light) {
    const double az = glm::radians(light.azimuth), el = glm::radians(light.elevation);
    return {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
}

struct SlicingRenderer::Impl {
    const BrickAtlas& atlas;
    SlicingMode mode;
    GlProgram eyePass, lightPass;
    GLuint tfTexture = 0;

    Impl(const BrickAtlas& a, SlicingMode m) : atlas(a), mode(m) {
        eyePass = GlProgram::graphics("inspect_slice.vert", "inspect_slice.frag",
                                      m == SlicingMode::HalfAngle ? std::vector<std::string>{"HALF_ANGLE"}
                                                                  : std::vector<std::string>{});
        if (m == SlicingMode::HalfAngle) lightPass = GlProgram::graphics("inspect_slice.vert", "inspect_slice.frag", {"LIGHT_PASS"});
        glCreateTextures(GL_TEXTURE_1D, 1, &tfTexture);
        glTextureStorage1D(tfTexture, 1, GL_RGBA32F, 256);
        glTextureParameteri(tfTexture, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(tfTexture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(tfTexture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        checkGlError("setting up the slicing renderer");
    }
    ~Impl() { glDeleteTextures(1, &tfTexture); }

    /// The uniforms both passes share: the atlas, the slices, the transfer function.
    void setVolumeUniforms(const GlProgram& p, const glm::mat4& viewProjection, const glm::dvec3& sliceNormal,
                           double spacing) const {
        const LevelPlan& plan = atlas.plan();
        p.use();
        glUniformMatrix4fv(p.uniform("viewProjection"), 1, GL_FALSE, glm::value_ptr(viewProjection));
        const glm::ivec3 slots = atlas.slotsPerAxis();
        glUniform3i(p.uniform("atlasSlots"), slots.x, slots.y, slots.z);
        glUniform3f(p.uniform("originVoxel"), float(plan.originVoxel.x), float(plan.originVoxel.y), float(plan.originVoxel.z));
        glUniform1f(p.uniform("levelScale"), float(plan.scale));
        glUniform3i(p.uniform("brickDims"), plan.brickDims.x, plan.brickDims.y, plan.brickDims.z);
        glUniform3f(p.uniform("sliceNormal"), float(sliceNormal.x), float(sliceNormal.y), float(sliceNormal.z));
        glUniform1f(p.uniform("spacing"), float(spacing));
    }
};

SlicingRenderer::SlicingRenderer(const BrickAtlas& atlas, SlicingMode mode) : impl_(std::make_unique<Impl>(atlas, mode)) {}
SlicingRenderer::~SlicingRenderer() = default;

namespace {

/// The vertex buffer and array of a slice stack, deleted with them.
struct SliceGeometry {
    GLuint buffer = 0, vao = 0;
    explicit SliceGeometry(const SliceStack& s) {
        glCreateBuffers(1, &buffer);
        glNamedBufferStorage(buffer, GLsizeiptr(std::max<std::size_t>(s.triangles.size(), 1) * sizeof(glm::vec3)),
                             s.triangles.empty() ? nullptr : s.triangles.data(), 0);
        glCreateVertexArrays(1, &vao);
        glVertexArrayVertexBuffer(vao, 0, buffer, 0, sizeof(glm::vec3));
        glEnableVertexArrayAttrib(vao, 0);
        glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribBinding(vao, 0, 0);
    }
    ~SliceGeometry() {
        glDeleteBuffers(1, &buffer);
        glDeleteVertexArrays(1, &vao);
    }
};

/// An orthographic view along -towardsLight that holds the sphere around `centre`.
glm::dmat4 lightViewProjection(const glm::dvec3& centre, double radius, const glm::dvec3& toLight) {
    const glm::dvec3 up = std::abs(toLight.z) > 0.999 ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1);
    const glm::dmat4 view = glm::lookAt(centre + 2.0 * radius * toLight, centre, up);
    return glm::ortho(-radius, radius, -radius, radius, 0.5 * radius, 3.5 * radius) * view;
}

} // namespace

SlicingResult SlicingRenderer::render(const Camera& camera, const SlicingSettings& s) {
    Impl& m = *impl_;
    const int w = camera.width, h = camera.height;
    const LevelPlan& plan = m.atlas.plan();
    const glm::dvec3 boxMin(plan.originVoxel);
    const glm::dvec3 boxMax = boxMin + glm::dvec3(plan.brickDims * (kBrickSize * plan.scale));
    // The camera looks down its -z: that axis in voxel coordinates.
    const glm::dvec3 forward = -glm::normalize(glm::dvec3(camera.view[0][2], camera.view[1][2], camera.view[2][2]));
    const glm::dvec3 toLight = towardsLight(s.light);
    const glm::dvec3 lightTravel = -toLight;

    // Texture slicing: planes facing the eye, drawn farthest first. Half-angle:
    // planes facing the half vector, drawn nearest the light first; the eye
    // sees them front to back when the light is behind it, else back to front.
    glm::dvec3 normal = forward;
    bool frontToBack = false;
    if (m.mode == SlicingMode::HalfAngle) {
        frontToBack = glm::dot(forward, lightTravel) >= 0.0;
        normal = glm::normalize(frontToBack ? forward + lightTravel : lightTravel - forward);
    }
    const double depth = boxDepth(boxMin, boxMax, normal);
    const double spacing = s.slices > 0 ? depth / double(s.slices) : double(plan.scale);
    const SliceStack stack = sliceStack(boxMin, boxMax, normal, spacing);
    const int slices = int(stack.first.size());
    SliceGeometry geometry(stack);

    const glm::dvec3 centre = 0.5 * (boxMin + boxMax);
    const double radius = 0.5 * glm::length(boxMax - boxMin);
    const glm::mat4 eyeViewProjection(camera.viewProjection());
    const glm::mat4 lightMatrix(lightViewProjection(centre, radius, toLight));
    const int lightSize = std::clamp(std::max(w, h), 64, 1024);

    glTextureSubImage1D(m.tfTexture, 0, 0, 256, GL_RGBA, GL_FLOAT, s.transferFunction.data());
    // Float targets: thousands of thin slices each add little, which 8 bits would round away.
    RenderTarget eye(w, h, {GL_RGBA32F});
    std::unique_ptr<RenderTarget> light;
    if (m.mode == SlicingMode::HalfAngle) light = std::make_unique<RenderTarget>(lightSize, lightSize, std::initializer_list<GLenum>{GL_RGBA32F});
    const float clear[4] = {0.0f, 0.0f, 0.0f, 0.0f};

    m.setVolumeUniforms(m.eyePass, eyeViewProjection, normal, spacing);
    const GlProgram& e = m.eyePass;
    glUniform3f(e.uniform("eye"), float(camera.eye.x), float(camera.eye.y), float(camera.eye.z));
    glUniform1i(e.uniform("rayFromEye"), 1);
    if (light) {
        glUniformMatrix4fv(e.uniform("lightViewProjection"), 1, GL_FALSE, glm::value_ptr(lightMatrix));
        glUniform1f(e.uniform("ambient"), float(s.ambient));
        m.setVolumeUniforms(m.lightPass, lightMatrix, normal, spacing);
        glUniform3f(m.lightPass.uniform("lightTravel"), float(lightTravel.x), float(lightTravel.y), float(lightTravel.z));
        glUniform1i(m.lightPass.uniform("rayFromEye"), 0);
    }
    glBindTextureUnit(1, m.atlas.indirectionTexture());
    glBindTextureUnit(2, m.atlas.densityTexture());
    glBindTextureUnit(4, m.tfTexture);
    if (light) glBindTextureUnit(5, light->textures[0]);
    glBindVertexArray(geometry.vao);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);

    glFinish();
    const auto start = std::chrono::steady_clock::now();
    glClearNamedFramebufferfv(eye.fbo, GL_COLOR, 0, clear);
    if (m.mode == SlicingMode::TextureSlicing) {
        // Premultiplied colour "over" what lies behind, farthest slice first.
        glBindFramebuffer(GL_FRAMEBUFFER, eye.fbo);
        glViewport(0, 0, w, h);
        glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
        for (int k = slices - 1; k >= 0; --k) glDrawArrays(GL_TRIANGLES, stack.first[std::size_t(k)], stack.count[std::size_t(k)]);
    } else {
        glClearNamedFramebufferfv(light->fbo, GL_COLOR, 0, clear);
        // The half vector points away from the light, so increasing k is the
        // light's front to back; for the eye it is front to back only when
        // the light is behind the viewer.
        for (int k = 0; k < slices; ++k) {
            const GLint first = stack.first[std::size_t(k)];
            const GLsizei count = stack.count[std::size_t(k)];
            if (count == 0) continue;
            glBindFramebuffer(GL_FRAMEBUFFER, eye.fbo);
            glViewport(0, 0, w, h);
            if (frontToBack) glBlendFunc(GL_ONE_MINUS_DST_ALPHA, GL_ONE); // "under"
            else glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);             // "over"
            m.eyePass.use();
            glDrawArrays(GL_TRIANGLES, first, count);
            // Opacity towards the light, front to back as the light sees it.
            glBindFramebuffer(GL_FRAMEBUFFER, light->fbo);
            glViewport(0, 0, lightSize, lightSize);
            glBlendFunc(GL_ONE_MINUS_DST_ALPHA, GL_ONE);
            m.lightPass.use();
            glDrawArrays(GL_TRIANGLES, first, count);
        }
    }
    glFinish();
    SlicingResult r;
    r.frameSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.slices = slices;
    glDisable(GL_BLEND);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    checkGlError("slicing");
    r.image = readRgbImage(eye.textures[0], w, h);
    return r;
}

} // namespace yv

#include "render/slice_renderer.h"

#include "core/error.h"
#include "gpu/gl_bindings.h"

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>

namespace yv {
namespace {

constexpr GLuint kBoxVertices = 14;   // one slab: a triangle strip (inspect_slices.vert)
constexpr GLintptr kPointsCommand = 16; // the points' draw command follows the boxes' in drawCommand_
constexpr std::uint64_t kKeyGroup = 256; // inspect_slices_keys.comp's local_size_x
/// The coarsest level of detail: a slab for 64 slices of a run.
constexpr int kLodLevels = 6;

/// glDrawArraysIndirect's command.
struct DrawCommand {
    GLuint count, instanceCount, first, baseInstance;
};

/// Refuses more slices than the driver's buffer textures (two texels each)
/// or storage blocks (the sort's, a word each) hold.
const SliceInstances& fitting(const SliceInstances& s) {
    GLint maxTexels = 0;
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
    GLint64 maxBlock = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxBlock);
    const std::uint64_t fit = std::min<std::uint64_t>(std::uint64_t(maxTexels) / 2, std::uint64_t(maxBlock) / 4);
    if (s.count() > fit)
        throw Error("--render slices: " + std::to_string(s.count()) + " slices exceed the driver's buffers (" +
                    std::to_string(fit) + " slices): draw a --region");
    return s;
}

/// The planes of `camera`'s frustum (a x + b y + c z + d >= 0 inside), unit normals.
std::array<glm::vec4, 6> frustumPlanes(const Camera& camera) {
    const glm::dmat4 m = camera.viewProjection();
    const auto row = [&](int r) { return glm::dvec4(m[0][r], m[1][r], m[2][r], m[3][r]); };
    std::array<glm::vec4, 6> planes;
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            const glm::dvec4 p = row(3) + (side ? -1.0 : 1.0) * row(axis);
            planes[2 * axis + side] = glm::vec4(p / glm::length(glm::dvec3(p)));
        }
    return planes;
}

GLuint maxComputeGroups() {
    GLint groups = 0;
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &groups);
    return GLuint(std::max(groups, 1));
}

} // namespace

SliceRenderer::SliceRenderer(const SliceInstances& slices, const SliceSettings& settings)
    : slices_(fitting(slices)), settings_(settings),
      program_(GlProgram::graphics("inspect_slices.vert", "inspect_slices.frag")),
      sliceTexture_(createTexture(GL_TEXTURE_BUFFER)), spanTexture_(createTexture(GL_TEXTURE_BUFFER)),
      orderArray_(createVertexArray()), twist_(slices.twist) {
    if (!(settings.lodPixels >= 0.0)) throw Error("slices: the level of detail's pixels must be 0 or more");
    const std::size_t records = std::max<std::size_t>(slices.records.size(), 2);
    sliceBuffer_.reserve(records * sizeof(glm::vec4), nullptr);
    if (!slices.records.empty())
        glNamedBufferSubData(sliceBuffer_.id(), 0, GLsizeiptr(slices.records.size() * sizeof(glm::vec4)), slices.records.data());
    glTextureBuffer(sliceTexture_.id(), GL_RGBA32F, sliceBuffer_.id());
    orderBuffer_.reserve(std::max<std::size_t>(slices.count(), 1) * sizeof(std::uint32_t), nullptr);
    // Every slab stands for its own slice until the level of detail says otherwise.
    spanBuffer_.reserve(std::max<std::size_t>(slices.count(), 1) * sizeof(std::uint32_t), nullptr);
    const GLuint one = 1;
    glClearNamedBufferData(spanBuffer_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &one);
    glTextureBuffer(spanTexture_.id(), GL_R32UI, spanBuffer_.id());
    const GLuint vao = orderArray_.id();
    glVertexArrayVertexBuffer(vao, 0, orderBuffer_.id(), 0, sizeof(std::uint32_t));
    glVertexArrayBindingDivisor(vao, 0, 1);
    glEnableVertexArrayAttrib(vao, 0);
    glVertexArrayAttribIFormat(vao, 0, 1, GL_UNSIGNED_INT, 0);
    glVertexArrayAttribBinding(vao, 0, 0);
    // The host's order draws every slice; the GPU's, the count its sort
    // kept, as boxes or as points.
    const GLuint hostCount = GLuint(settings.sortOnHost ? slices.count() : 0);
    const DrawCommand commands[2] = {{kBoxVertices, hostCount, 0, 0}, {1, 0, 0, 0}};
    static_assert(sizeof(DrawCommand) == kPointsCommand);
    drawCommand_.reserve(sizeof(commands), nullptr);
    glNamedBufferSubData(drawCommand_.id(), 0, sizeof(commands), commands);
    if (!settings.sortOnHost) {
        maxGroups_ = maxComputeGroups();
        keys_ = GlProgram::compute("inspect_slices_keys.comp");
        sort_.emplace(slices.count(), maxGroups_);
        largestBuffer_.reserve(sizeof(GLuint), nullptr);
        choose_ = GlProgram::compute("inspect_slices_choose.comp");
        if (settings.primitive == SlicePrimitive::Tiles ||
            (settings.primitive == SlicePrimitive::Auto && settings.onGpu))
            tiles_.emplace(slices.count(), maxGroups_,
                           settings.maxTilePairs ? settings.maxTilePairs : defaultMaxTilePairs(slices.count()));
        if (settings.primitive == SlicePrimitive::Auto || settings.primitive == SlicePrimitive::Points) {
            pointsProgram_ = GlProgram::graphics("inspect_slices.vert", "inspect_slices.frag", {"SLAB_POINTS 1"});
            float range[2] = {1.0f, 1.0f};
            glGetFloatv(GL_ALIASED_POINT_SIZE_RANGE, range);
            pointPixels_ = std::min(range[1], kSlicePointPixels);
        }
    }
    checkGlError("uploading the slices");
}

void SliceRenderer::setSliceLod(double pixels) {
    YV_CHECK(pixels >= 0.0);
    settings_.lodPixels = pixels;
}

void SliceRenderer::prepare(const Camera& camera) {
    const std::uint64_t n = slices_.count();
    if (settings_.sortOnHost) {
        sortBackToFront(slices_, camera.eye, hostOrder_);
        if (n) glNamedBufferSubData(orderBuffer_.id(), 0, GLsizeiptr(n * sizeof(std::uint32_t)), hostOrder_.data());
        drawn_ = n;
        return;
    }
    countsRead_ = true;
    drawn_ = 0;
    drewPoints_ = drewTiles_ = false;
    if (n == 0) {
        const GLuint none = 0;
        glClearNamedBufferData(drawCommand_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &none);
        return;
    }
    keys_.use();
    glUniform1ui(keys_.uniform("uSlices"), GLuint(n));
    const glm::vec3 eye(camera.eye); // as sortBackToFront rounds it
    glUniform3fv(keys_.uniform("uEye"), 1, glm::value_ptr(eye));
    glUniform1f(keys_.uniform("uRadius"), slices_.radius);
    glUniform1i(keys_.uniform("uCull"), settings_.cull ? 1 : 0);
    const std::array<glm::vec4, 6> planes = frustumPlanes(camera);
    glUniform4fv(keys_.uniform("uPlanes"), 6, glm::value_ptr(planes[0]));
    // A length l at depth z spans l * focal / z pixels (projection[1][1] = 1 / tan(half the field of view)).
    glUniform1i(keys_.uniform("uLodLevels"), settings_.lodPixels > 0.0 ? kLodLevels : 0);
    glUniform1f(keys_.uniform("uLodPixels"), float(settings_.lodPixels));
    glUniform1f(keys_.uniform("uFocalPixels"), float(camera.projection[1][1] * 0.5 * camera.height));
    const glm::dmat4 inverseView = glm::inverse(camera.view);
    const glm::vec3 forward(-glm::normalize(glm::dvec3(inverseView[2])));
    glUniform3fv(keys_.uniform("uForward"), 1, glm::value_ptr(forward));
    if (tiles_) tiles_->setUpKeysPass(keys_, camera, GLuint(n));
    else glUniform1i(keys_.uniform("uTiles"), 0);
    glBindTextureUnit(kSliceTableUnit, sliceTexture_.id());
    sort_->keys().bindStorage(kSortKeysInBinding);
    sort_->values().bindStorage(kSortValuesInBinding);
    spanBuffer_.bindStorage(kSliceSpansBinding);
    const GLuint zero = 0;
    glClearNamedBufferData(largestBuffer_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    largestBuffer_.bindStorage(kSliceLargestBinding);
    glDispatchCompute(GLuint(std::min<std::uint64_t>((n + kKeyGroup - 1) / kKeyGroup, maxGroups_)), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    if (tiles_) {
        if ((drewTiles_ = tiles_->prepare(camera, *sort_, GLuint(n)))) {
            drawn_ = tiles_->kept();
            const GLuint none = 0; // neither raster draw
            glClearNamedBufferData(drawCommand_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &none);
            return;
        }
    }
    sort_->sort(GLuint(n), orderBuffer_);
    // The kept count becomes the instances of one draw, points' or boxes',
    // on the GPU: the host waits for none of it. It reads both draws'
    // instances for the report, once the frame is done (readCounts).
    choose_.use();
    glUniform1f(choose_.uniform("uPointPixels"), pointPixels_);
    sort_->kept().bindStorage(kSortKeptBinding);
    largestBuffer_.bindStorage(kSliceLargestBinding);
    drawCommand_.bindStorage(kSliceDrawsBinding);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_COMMAND_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                    GL_BUFFER_UPDATE_BARRIER_BIT);
    readback_.startCopy({{drawCommand_.id(), offsetof(DrawCommand, instanceCount), 4},
                         {drawCommand_.id(), kPointsCommand + offsetof(DrawCommand, instanceCount), 4}},
                        nullptr);
    countsRead_ = false;
    checkGlError("sorting the slices");
}

void SliceRenderer::readCounts() const {
    if (countsRead_) return;
    GLuint instances[2] = {0, 0}; // boxes', points'
    std::memcpy(instances, readback_.waitForCopy(), sizeof instances);
    drawn_ = instances[0] + instances[1];
    drewPoints_ = instances[1] > 0;
    countsRead_ = true;
}

void SliceRenderer::describe(RenderReport& report) const {
    readCounts();
    report.slices = drawn_;
    report.garmentSlices = slices_.count();
    report.slicePrimitive = drewTiles_ ? "tiles" : drewPoints_ ? "points" : "boxes";
}

void SliceRenderer::useProgram(const GlProgram& program, const Camera& camera) const {
    program.use();
    const glm::mat4 vp(camera.viewProjection());
    glUniformMatrix4fv(program.uniform("viewProjection"), 1, GL_FALSE, glm::value_ptr(vp));
    const glm::vec3 eye(camera.eye);
    glUniform3fv(program.uniform("eye"), 1, glm::value_ptr(eye));
    // Parallel light from over the viewer's shoulder: the camera's up and back.
    const glm::dmat4 inverseView = glm::inverse(camera.view);
    const glm::vec3 light(glm::normalize(glm::dvec3(inverseView[2]) + 0.5 * glm::dvec3(inverseView[1])));
    glUniform3fv(program.uniform("lightDirection"), 1, glm::value_ptr(light));
    glUniform3fv(program.uniform("albedo"), 1, glm::value_ptr(kSliceAlbedo));
    glUniform1f(program.uniform("radius"), slices_.radius);
    glUniform1f(program.uniform("twist"), twist_);
    glUniform1f(program.uniform("opacityPerVoxel"), kSliceOpacityTimesRadius / std::max(slices_.radius, 1e-6f));
}

void SliceRenderer::draw(const Frame& frame) {
    const Camera& camera = frame.camera;
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA); // premultiplied "over", back to front
    glBindTextureUnit(kSliceTableUnit, sliceTexture_.id());
    glBindTextureUnit(kSliceSpansUnit, spanTexture_.id());
    if (drewTiles_) {
        useProgram(tiles_->compositeProgram(), camera);
        tiles_->draw(camera);
        glDisable(GL_BLEND);
        return;
    }
    glBindVertexArray(orderArray_.id());
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, drawCommand_.id());
    // Both draws: the GPU gave one of them the slices kept and the other none.
    useProgram(program_, camera);
    glDrawArraysIndirect(GL_TRIANGLE_STRIP, nullptr);
    if (pointPixels_ > 0.0f) {
        // A margin of half the largest point around the picture, so that a
        // point whose centre lies outside it still draws its part inside
        // (GL drops a point whose centre is outside the viewport). The
        // frame's viewport starts at its target's corner (RenderTarget::bind),
        // where the fragment shader counts its pixels from.
        useProgram(pointsProgram_, camera);
        GLint viewport[4];
        glGetIntegerv(GL_VIEWPORT, viewport);
        const int width = viewport[2], height = viewport[3], margin = int(std::ceil(pointPixels_ / 2.0f)) + 1;
        const glm::vec2 pixels{float(width), float(height)};
        const glm::vec2 guard(pixels / (pixels + float(2 * margin)));
        glUniform2fv(pointsProgram_.uniform("viewportPixels"), 1, glm::value_ptr(pixels));
        glUniform2fv(pointsProgram_.uniform("guardScale"), 1, glm::value_ptr(guard));
        const glm::mat4 inverseVp(glm::inverse(camera.viewProjection()));
        glUniformMatrix4fv(pointsProgram_.uniform("inverseViewProjection"), 1, GL_FALSE, glm::value_ptr(inverseVp));
        glViewport(viewport[0] - margin, viewport[1] - margin, width + 2 * margin, height + 2 * margin);
        glEnable(GL_PROGRAM_POINT_SIZE);
        glDrawArraysIndirect(GL_POINTS, reinterpret_cast<const void*>(kPointsCommand));
        glDisable(GL_PROGRAM_POINT_SIZE);
        glViewport(viewport[0], viewport[1], width, height);
    }
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    glDisable(GL_BLEND);
    checkGlError("drawing the slices");
}

std::vector<std::uint32_t> SliceRenderer::drawOrder() {
    readCounts();
    if (drewTiles_) return {};
    std::vector<std::uint32_t> order(drawn_);
    if (drawn_) std::memcpy(order.data(), readback_.read(orderBuffer_.id(), drawn_ * 4, nullptr), drawn_ * 4);
    return order;
}

std::vector<std::uint32_t> SliceRenderer::spans() {
    const std::uint64_t n = slices_.count();
    std::vector<std::uint32_t> spans(n);
    if (n) std::memcpy(spans.data(), readback_.read(spanBuffer_.id(), n * 4, nullptr), n * 4);
    return spans;
}

} // namespace yv

#include "inspect/volumetric_triangles.h"

#include "core/error.h"
#include "gpu/egl_context.h"
#include "gpu/gl_program.h"
#include "inspect/transfer_function.h"

#include <glm/common.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

namespace yv {
namespace {

/// One slice as the vertex shader reads it: centre and thickness, then the
/// square's half-edges (right and up times the radius), voxel units.
struct GpuSlice {
    float centreThickness[4];
    float right[4];
    float up[4];
};
static_assert(sizeof(GpuSlice) == 48, "inspect_voltri.vert reads three vec4 attributes a slice");

/// Slices are placed on the host and drawn in batches of this many, so the
/// garment's slices are never all held at once.
constexpr std::size_t kBatchSlices = 1u << 18;

/// The in-plane blur: half a voxel, the voxelizer's reach of one sample.
constexpr float kBlurVoxels = 0.5f;
/// Largest sample grid a side per triangle (the blur widens past it).
constexpr int kMaxDivisions = 16;

int floorTo8(double v) { return int(std::floor(v / 8.0)) * 8; }
int ceilTo8(double v) { return int(std::ceil(v / 8.0)) * 8; }

} // namespace

VoxelBox sliceBox(const SlicePlan& plan, const VoxelGrid& grid) {
    const double reach = plan.options.radius * std::sqrt(2.0) + plan.maxSpacing;
    const glm::dvec3 lo = (plan.curveMin - reach - grid.origin) / grid.voxelSize;
    const glm::dvec3 hi = (plan.curveMax + reach - grid.origin) / grid.voxelSize;
    VoxelBox box;
    for (int a = 0; a < 3; ++a) {
        box.min[a] = std::max(floorTo8(lo[a]), 0);
        box.max[a] = std::min(ceilTo8(hi[a]), ceilTo8(grid.dims[a]));
    }
    return box;
}

RenderReport renderVolumetricTriangles(const SlicePlan& plan, const VoxelGrid& grid, const VoxelBox& box,
                                       const RenderRequest& request, double yarnDensity) {
    if (plan.sliceCount == 0) throw Error("nothing to render: the garment has no slices");
    if (box.empty()) throw Error("nothing to render: the slices reach no voxel of the grid");
    const TransferFunction tf = loadTransferFunction(request.transferFunction);
    GlContext context(GlContextOptions{request.device, false});
    RenderReport report;
    report.renderer = context.info().renderer;

    const GlProgram program = GlProgram::graphicsWithGeometry("inspect_voltri.vert", "inspect_voltri.geom", "inspect_voltri.frag");
    GLuint buffer = 0, vao = 0, fbo = 0, target = 0;
    glCreateBuffers(1, &buffer);
    glNamedBufferStorage(buffer, GLsizeiptr(kBatchSlices * sizeof(GpuSlice)), nullptr, GL_DYNAMIC_STORAGE_BIT);
    glCreateVertexArrays(1, &vao);
    glVertexArrayVertexBuffer(vao, 0, buffer, 0, sizeof(GpuSlice));
    for (GLuint a = 0; a < 3; ++a) {
        glEnableVertexArrayAttrib(vao, a);
        glVertexArrayAttribFormat(vao, a, a == 0 ? 4 : 3, GL_FLOAT, GL_FALSE, a * 16u);
        glVertexArrayAttribBinding(vao, a, 0);
    }
    const int w = request.width, h = request.height;
    glCreateTextures(GL_TEXTURE_2D, 1, &target);
    glTextureStorage2D(target, 1, GL_R32F, w, h);
    glCreateFramebuffers(1, &fbo);
    glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, target, 0);
    struct Cleanup {
        GLuint buffer, vao, fbo, target;
        ~Cleanup() {
            glDeleteBuffers(1, &buffer);
            glDeleteVertexArrays(1, &vao);
            glDeleteFramebuffers(1, &fbo);
            glDeleteTextures(1, &target);
        }
    } cleanup{buffer, vao, fbo, target};
    if (glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Error("the render target is not complete (image size too large for the driver?)");
    checkGlError("setting up volumetric triangles");

    const Camera camera = frameBox(box, request.view, w, h);
    const glm::mat4 vp(camera.viewProjection());
    const glm::mat4 inv(glm::inverse(camera.viewProjection()));
    const double inverseVoxel = 1.0 / grid.voxelSize;
    std::vector<GpuSlice> batch;
    batch.reserve(kBatchSlices);

    // One frame: every slice placed, drawn, and the absorbances summed.
    const auto drawFrame = [&] {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glViewport(0, 0, w, h);
        const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        glClearNamedFramebufferfv(fbo, GL_COLOR, 0, zero);
        glDisable(GL_DEPTH_TEST);
        glDisable(GL_CULL_FACE);
        glEnable(GL_BLEND);
        glBlendEquation(GL_FUNC_ADD);
        glBlendFunc(GL_ONE, GL_ONE);
        program.use();
        glUniformMatrix4fv(program.uniform("viewProjection"), 1, GL_FALSE, glm::value_ptr(vp));
        glUniformMatrix4fv(program.uniform("inverseViewProjection"), 1, GL_FALSE, glm::value_ptr(inv));
        glUniform2f(program.uniform("viewport"), float(w), float(h));
        glUniform3f(program.uniform("eye"), float(camera.eye.x), float(camera.eye.y), float(camera.eye.z));
        glUniform1f(program.uniform("pixelAngle"),
                    float(2.0 * std::tan(glm::radians(kFieldOfViewDegrees) / 2.0) / double(h)));
        glUniform1f(program.uniform("blurVoxels"), kBlurVoxels);
        glUniform1i(program.uniform("maxDivisions"), kMaxDivisions);
        glBindVertexArray(vao);
        const auto flush = [&] {
            if (batch.empty()) return;
            glNamedBufferSubData(buffer, 0, GLsizeiptr(batch.size() * sizeof(GpuSlice)), batch.data());
            glDrawArrays(GL_POINTS, 0, GLsizei(batch.size()));
            batch.clear();
        };
        for (const SegmentRecord& segment : plan.segments)
            for (std::uint32_t k = 0; k < segment.sliceCount; ++k) {
                const Slice s = placeSlice(segment, k);
                const glm::vec3 c((s.center - grid.origin) * inverseVoxel);
                const glm::vec3 r(s.right * (plan.options.radius * inverseVoxel));
                const glm::vec3 u(s.up * (plan.options.radius * inverseVoxel));
                batch.push_back({{c.x, c.y, c.z, float(s.thickness * inverseVoxel)}, {r.x, r.y, r.z, 0.0f}, {u.x, u.y, u.z, 0.0f}});
                if (batch.size() == kBatchSlices) flush();
            }
        flush();
        glDisable(GL_BLEND);
        glFinish();
        checkGlError("drawing volumetric triangles");
    };
    std::vector<double> frames;
    for (int i = 0; i < std::max(1, request.repeat); ++i) {
        const auto start = std::chrono::steady_clock::now();
        drawFrame();
        frames.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    std::sort(frames.begin(), frames.end());
    report.frameSeconds = frames[frames.size() / 2];
    report.bestFrameSeconds = frames.front();

    std::vector<float> absorbance(std::size_t(w) * std::size_t(h));
    glGetTextureImage(target, 0, GL_RED, GL_FLOAT, GLsizei(absorbance.size() * sizeof(float)), absorbance.data());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    checkGlError("reading volumetric triangles back");
    // The absorbance is the length of yarn on the ray, in voxels; the
    // transfer function's opacity per voxel at the yarn's density turns it
    // into opacity, its colour is the fibre's. Over black, as the ray cast.
    const std::size_t entry = std::size_t(std::lround(std::clamp(yarnDensity, 0.0, 1.0) * double(tf.size() - 1)));
    const glm::vec4 fibre = tf[entry];
    const double extinction = -std::log(1.0 - std::min(double(fibre.a), 0.9999));
    report.image = RgbImage(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double tau = std::max(0.0f, absorbance[std::size_t(h - 1 - y) * std::size_t(w) + std::size_t(x)]);
            const double alpha = 1.0 - std::exp(-extinction * tau);
            std::uint8_t* p = report.image.at(x, y);
            for (int k = 0; k < 3; ++k) p[k] = std::uint8_t(std::lround(255.0 * std::clamp(double(fibre[k]) * alpha, 0.0, 1.0)));
        }
    report.fineBricks = report.levelBricks = 0;
    return report;
}

} // namespace yv

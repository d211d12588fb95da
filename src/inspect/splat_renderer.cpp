#include "inspect/splat_renderer.h"

#include "core/error.h"
#include "gpu/gl_program.h"
#include "inspect/render_target.h"

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

namespace yv {

struct SplatRenderer::Impl {
    const BrickAtlas& atlas;
    GlProgram program;
    GLuint tfTexture = 0, orderBuffer = 0, vao = 0;
    std::vector<glm::ivec4> bricks; ///< level brick (xyz) and atlas slot (w) of each occupied brick
    float maxPointSize = 64.0f;

    explicit Impl(const BrickAtlas& a) : atlas(a) {
        program = GlProgram::graphics("inspect_splat.vert", "inspect_splat.frag");
        // The atlas keeps brick -> slot; read it back for slot -> brick.
        const glm::ivec3 d = a.plan().brickDims;
        std::vector<std::uint32_t> slotOf(std::size_t(d.x) * std::size_t(d.y) * std::size_t(d.z));
        glPixelStorei(GL_PACK_ALIGNMENT, 4);
        glGetTextureImage(a.indirectionTexture(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT,
                          GLsizei(slotOf.size() * sizeof(std::uint32_t)), slotOf.data());
        for (int z = 0; z < d.z; ++z)
            for (int y = 0; y < d.y; ++y)
                for (int x = 0; x < d.x; ++x)
                    if (const std::uint32_t s = slotOf[std::size_t(x) + std::size_t(d.x) * (std::size_t(y) + std::size_t(d.y) * std::size_t(z))])
                        bricks.emplace_back(x, y, z, int(s - 1));
        glCreateBuffers(1, &orderBuffer);
        glNamedBufferStorage(orderBuffer, GLsizeiptr(std::max<std::size_t>(bricks.size(), 1) * sizeof(glm::ivec4)), nullptr,
                             GL_DYNAMIC_STORAGE_BIT);
        glCreateVertexArrays(1, &vao);
        glCreateTextures(GL_TEXTURE_1D, 1, &tfTexture);
        glTextureStorage1D(tfTexture, 1, GL_RGBA32F, 256);
        glTextureParameteri(tfTexture, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(tfTexture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(tfTexture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        float range[2] = {1.0f, 64.0f};
        glGetFloatv(GL_ALIASED_POINT_SIZE_RANGE, range);
        maxPointSize = range[1];
        checkGlError("setting up the splat renderer");
    }
    ~Impl() {
        glDeleteTextures(1, &tfTexture);
        glDeleteBuffers(1, &orderBuffer);
        glDeleteVertexArrays(1, &vao);
    }
};

SplatRenderer::SplatRenderer(const BrickAtlas& atlas) : impl_(std::make_unique<Impl>(atlas)) {}
SplatRenderer::~SplatRenderer() = default;

SplatResult SplatRenderer::render(const Camera& camera, const SplatSettings& s) {
    Impl& m = *impl_;
    const int w = camera.width, h = camera.height;
    const LevelPlan& plan = m.atlas.plan();
    const glm::dvec3 forward = -glm::normalize(glm::dvec3(camera.view[0][2], camera.view[1][2], camera.view[2][2]));
    // Planes of voxels within a brick run across the axis nearest the view
    // direction (outermost), then the next nearest.
    std::array<int, 3> axes = {0, 1, 2};
    std::sort(axes.begin(), axes.end(), [&](int a, int b) { return std::abs(forward[a]) > std::abs(forward[b]); });
    glTextureSubImage1D(m.tfTexture, 0, 0, 256, GL_RGBA, GL_FLOAT, s.transferFunction.data());
    RenderTarget target(w, h, {GL_RGBA32F});
    const float clear[4] = {0.0f, 0.0f, 0.0f, 0.0f};

    const GlProgram& p = m.program;
    p.use();
    const glm::mat4 vp(camera.viewProjection());
    glUniformMatrix4fv(p.uniform("viewProjection"), 1, GL_FALSE, glm::value_ptr(vp));
    glUniform3f(p.uniform("eye"), float(camera.eye.x), float(camera.eye.y), float(camera.eye.z));
    const glm::ivec3 slots = m.atlas.slotsPerAxis();
    glUniform3i(p.uniform("atlasSlots"), slots.x, slots.y, slots.z);
    glUniform3f(p.uniform("originVoxel"), float(plan.originVoxel.x), float(plan.originVoxel.y), float(plan.originVoxel.z));
    glUniform1f(p.uniform("levelScale"), float(plan.scale));
    glUniform3i(p.uniform("planeAxes"), axes[0], axes[1], axes[2]);
    glUniform1f(p.uniform("sigma"), float(s.sigmaVoxels));
    // Pixels per voxel of length at clip w = 1.
    glUniform1f(p.uniform("pixelsPerUnit"), float(camera.projection[1][1] * 0.5 * h));
    glUniform1f(p.uniform("maxPointSize"), m.maxPointSize);
    glBindTextureUnit(2, m.atlas.densityTexture());
    glBindTextureUnit(4, m.tfTexture);
    glBindVertexArray(m.vao);
    glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
    glViewport(0, 0, w, h);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_PROGRAM_POINT_SIZE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);

    glFinish();
    const auto start = std::chrono::steady_clock::now();
    // Farthest brick first: GL blends in the order primitives are given.
    const double brickSpan = double(kBrickSize * plan.scale);
    std::vector<double> distance(m.bricks.size());
    for (std::size_t i = 0; i < m.bricks.size(); ++i) {
        const glm::dvec3 centre = glm::dvec3(plan.originVoxel) + (glm::dvec3(glm::ivec3(m.bricks[i])) + 0.5) * brickSpan;
        distance[i] = glm::length(centre - camera.eye);
    }
    std::vector<std::size_t> order(m.bricks.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return distance[a] > distance[b]; });
    std::vector<glm::ivec4> sorted(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) sorted[i] = m.bricks[order[i]];
    if (!sorted.empty())
        glNamedBufferSubData(m.orderBuffer, 0, GLsizeiptr(sorted.size() * sizeof(glm::ivec4)), sorted.data());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, m.orderBuffer);
    glClearNamedFramebufferfv(target.fbo, GL_COLOR, 0, clear);
    glDrawArrays(GL_POINTS, 0, GLsizei(sorted.size() * 512u));
    glFinish();
    SplatResult r;
    r.frameSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.splats = std::uint64_t(sorted.size()) * 512u;
    glDisable(GL_BLEND);
    glDisable(GL_PROGRAM_POINT_SIZE);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    checkGlError("splatting");
    r.image = readRgbImage(target.textures[0], w, h);
    return r;
}

} // namespace yv

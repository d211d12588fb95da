#include "render/splat_renderer.h"

#include "core/error.h"

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace yv {
namespace {

/// The occupied bricks of `atlas`: level brick and atlas slot, read back
/// from the indirection texture (the atlas keeps brick -> slot).
std::vector<glm::ivec4> occupiedSlots(const BrickAtlas& atlas) {
    const glm::ivec3 d = atlas.plan().brickDims;
    std::vector<std::uint32_t> slotOf(std::size_t(d.x) * std::size_t(d.y) * std::size_t(d.z));
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTextureImage(atlas.indirectionTexture(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT,
                      GLsizei(slotOf.size() * sizeof(std::uint32_t)), slotOf.data());
    std::vector<glm::ivec4> bricks;
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x)
                if (const std::uint32_t s = slotOf[std::size_t(x) + std::size_t(d.x) * (std::size_t(y) + std::size_t(d.y) * std::size_t(z))])
                    bricks.emplace_back(x, y, z, int(s - 1));
    return bricks;
}

} // namespace

SplatRenderer::SplatRenderer(const BrickAtlas& atlas, const SplatSettings& settings)
    : atlas_(atlas), settings_(settings), program_(GlProgram::graphics("inspect_splat.vert", "inspect_splat.frag")),
      transferFunction_(settings.transferFunction), emptyArray_(createVertexArray()), bricks_(occupiedSlots(atlas)) {
    orderBuffer_.reserve(std::max<std::size_t>(bricks_.size(), 1) * sizeof(glm::ivec4), nullptr);
    float range[2] = {1.0f, 64.0f};
    glGetFloatv(GL_ALIASED_POINT_SIZE_RANGE, range);
    maxPointSize_ = range[1];
    checkGlError("setting up the splat renderer");
}

void SplatRenderer::setUniforms(const Camera& camera) const {
    const LevelPlan& plan = atlas_.plan();
    const glm::dvec3 forward = -glm::normalize(glm::dvec3(camera.view[0][2], camera.view[1][2], camera.view[2][2]));
    // Planes of voxels within a brick run across the axis nearest the view
    // direction (outermost), then the next nearest.
    std::array<int, 3> axes = {0, 1, 2};
    std::sort(axes.begin(), axes.end(), [&](int a, int b) { return std::abs(forward[a]) > std::abs(forward[b]); });
    const GlProgram& p = program_;
    p.use();
    const glm::mat4 vp(camera.viewProjection());
    glUniformMatrix4fv(p.uniform("viewProjection"), 1, GL_FALSE, glm::value_ptr(vp));
    glUniform3f(p.uniform("eye"), float(camera.eye.x), float(camera.eye.y), float(camera.eye.z));
    const glm::ivec3 slots = atlas_.slotsPerAxis();
    glUniform3i(p.uniform("atlasSlots"), slots.x, slots.y, slots.z);
    glUniform3f(p.uniform("originVoxel"), float(plan.originVoxel.x), float(plan.originVoxel.y), float(plan.originVoxel.z));
    glUniform1f(p.uniform("levelScale"), float(plan.scale));
    glUniform3i(p.uniform("planeAxes"), axes[0], axes[1], axes[2]);
    glUniform1f(p.uniform("sigma"), float(settings_.sigmaVoxels));
    // Pixels per voxel of length at clip w = 1.
    glUniform1f(p.uniform("pixelsPerUnit"), float(camera.projection[1][1] * 0.5 * camera.height));
    glUniform1f(p.uniform("maxPointSize"), maxPointSize_);
}

void SplatRenderer::draw(const Frame& frame) {
    const Camera& camera = frame.camera;
    setUniforms(camera);
    glBindTextureUnit(2, atlas_.densityTexture());
    glBindTextureUnit(4, transferFunction_.id());
    glBindVertexArray(emptyArray_.id());
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_PROGRAM_POINT_SIZE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);

    // Farthest brick first: GL blends in the order primitives are given.
    const LevelPlan& plan = atlas_.plan();
    const double brickSpan = double(kBrickSize * plan.scale);
    std::vector<double> distance(bricks_.size());
    for (std::size_t i = 0; i < bricks_.size(); ++i) {
        const glm::dvec3 centre = glm::dvec3(plan.originVoxel) + (glm::dvec3(glm::ivec3(bricks_[i])) + 0.5) * brickSpan;
        distance[i] = glm::length(centre - camera.eye);
    }
    std::vector<std::size_t> order(bricks_.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return distance[a] > distance[b]; });
    std::vector<glm::ivec4> sorted(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) sorted[i] = bricks_[order[i]];
    if (!sorted.empty())
        glNamedBufferSubData(orderBuffer_.id(), 0, GLsizeiptr(sorted.size() * sizeof(glm::ivec4)), sorted.data());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, orderBuffer_.id());
    glDrawArrays(GL_POINTS, 0, GLsizei(sorted.size() * 512u));
    glDisable(GL_BLEND);
    glDisable(GL_PROGRAM_POINT_SIZE);
    checkGlError("splatting");
}

} // namespace yv

#include "render/volumetric_triangles.h"

#include "core/error.h"

#include <glm/common.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
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

const SlicePlan& withSlices(const SlicePlan& plan) {
    if (plan.sliceCount == 0) throw Error("nothing to render: the garment has no slices");
    return plan;
}

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

VolumetricTriangleRenderer::VolumetricTriangleRenderer(const SlicePlan& plan, const VoxelGrid& grid,
                                                       const TransferFunction& tf, double yarnDensity)
    : plan_(withSlices(plan)), grid_(grid), tf_(tf), yarnDensity_(yarnDensity),
      program_(GlProgram::graphicsWithGeometry("inspect_voltri.vert", "inspect_voltri.geom", "inspect_voltri.frag")),
      batchArray_(createVertexArray()) {
    batchBuffer_.reserve(kBatchSlices * sizeof(GpuSlice), nullptr);
    const GLuint vao = batchArray_.id();
    glVertexArrayVertexBuffer(vao, 0, batchBuffer_.id(), 0, sizeof(GpuSlice));
    for (GLuint a = 0; a < 3; ++a) {
        glEnableVertexArrayAttrib(vao, a);
        glVertexArrayAttribFormat(vao, a, a == 0 ? 4 : 3, GL_FLOAT, GL_FALSE, a * 16u);
        glVertexArrayAttribBinding(vao, a, 0);
    }
    checkGlError("setting up volumetric triangles");
}

void VolumetricTriangleRenderer::setUniforms(const Camera& camera) const {
    const glm::mat4 vp(camera.viewProjection());
    const glm::mat4 inv(glm::inverse(camera.viewProjection()));
    program_.use();
    glUniformMatrix4fv(program_.uniform("viewProjection"), 1, GL_FALSE, glm::value_ptr(vp));
    glUniformMatrix4fv(program_.uniform("inverseViewProjection"), 1, GL_FALSE, glm::value_ptr(inv));
    glUniform2f(program_.uniform("viewport"), float(camera.width), float(camera.height));
    glUniform3f(program_.uniform("eye"), float(camera.eye.x), float(camera.eye.y), float(camera.eye.z));
    glUniform1f(program_.uniform("pixelAngle"),
                float(2.0 * std::tan(glm::radians(kFieldOfViewDegrees) / 2.0) / double(camera.height)));
    glUniform1f(program_.uniform("blurVoxels"), kBlurVoxels);
    glUniform1i(program_.uniform("maxDivisions"), kMaxDivisions);
}

void VolumetricTriangleRenderer::draw(const Frame& frame) {
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE, GL_ONE); // absorbances add up
    setUniforms(frame.camera);
    glBindVertexArray(batchArray_.id());
    std::vector<GpuSlice> batch;
    batch.reserve(kBatchSlices);
    const auto flush = [&] {
        if (batch.empty()) return;
        glNamedBufferSubData(batchBuffer_.id(), 0, GLsizeiptr(batch.size() * sizeof(GpuSlice)), batch.data());
        glDrawArrays(GL_POINTS, 0, GLsizei(batch.size()));
        batch.clear();
    };
    const double inverseVoxel = 1.0 / grid_.voxelSize;
    for (const SegmentRecord& segment : plan_.segments)
        for (std::uint32_t k = 0; k < segment.sliceCount; ++k) {
            const Slice s = placeSlice(segment, k);
            const glm::vec3 c((s.center - grid_.origin) * inverseVoxel);
            const glm::vec3 r(s.right * (plan_.options.radius * inverseVoxel));
            const glm::vec3 u(s.up * (plan_.options.radius * inverseVoxel));
            batch.push_back({{c.x, c.y, c.z, float(s.thickness * inverseVoxel)}, {r.x, r.y, r.z, 0.0f}, {u.x, u.y, u.z, 0.0f}});
            if (batch.size() == kBatchSlices) flush();
        }
    flush();
    glDisable(GL_BLEND);
    checkGlError("drawing volumetric triangles");
}

PendingRgbImage VolumetricTriangleRenderer::startPicture(const Frame& frame) {
    const int w = frame.target.width(), h = frame.target.height();
    const std::vector<float> absorbance = readRedFloats(frame.target.texture(0), w, h);
    // The absorbance is the length of yarn on the ray, in voxels; the
    // transfer function's opacity per voxel at the yarn's density turns it
    // into opacity, its colour is the fibre's. Over black, as the ray cast.
    const std::size_t entry = std::size_t(std::lround(std::clamp(yarnDensity_, 0.0, 1.0) * double(tf_.size() - 1)));
    const glm::vec4 fibre = tf_[entry];
    const double extinction = -std::log(1.0 - std::min(double(fibre.a), 0.9999));
    RgbImage image(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double tau = std::max(0.0f, absorbance[std::size_t(y) * std::size_t(w) + std::size_t(x)]);
            const double alpha = 1.0 - std::exp(-extinction * tau);
            std::uint8_t* p = image.at(x, y);
            for (int k = 0; k < 3; ++k) p[k] = std::uint8_t(std::lround(255.0 * std::clamp(double(fibre[k]) * alpha, 0.0, 1.0)));
        }
    return PendingRgbImage(std::move(image));
}

} // namespace yv

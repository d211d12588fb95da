#include "gpu/dense_voxelizer.h"

#include "core/error.h"
#include "gpu/cross_section_texture.h"
#include "gpu/egl_context.h"
#include "gpu/gl_bindings.h"
#include "gpu/gl_buffer.h"
#include "gpu/gl_objects.h"
#include "gpu/gl_program.h"
#include "gpu/gpu_layout.h"
#include "gpu/slice_placer.h"

#include <epoxy/gl.h>
#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>

namespace yv {
namespace {

/// Seconds of the GL commands issued by `work`, the GPU drained at both ends
/// (timer queries would be finer, but llvmpipe answers them with garbage).
template <class F> double timedGpu(F&& work) {
    glFinish();
    const auto start = std::chrono::steady_clock::now();
    work();
    glFinish();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string dimsText(const glm::ivec3& d) {
    return std::to_string(d.x) + "x" + std::to_string(d.y) + "x" + std::to_string(d.z);
}

/// Axis from the paper's angles: theta = acos(z) / pi, phi = (atan(y, x) + pi) / (2 pi).
glm::vec3 decodeAngles(std::uint8_t theta, std::uint8_t phi) {
    const double t = theta / 255.0 * M_PI, p = phi / 255.0 * 2.0 * M_PI - M_PI;
    return glm::vec3(canonicalAxis({std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)}));
}

/// Bricks with any non-zero density among the brick layers of one z slab
/// (`nz` slices from `z0`, a multiple of 8), each channel W*H*nz bytes.
void convertSlab(const VoxelGrid& grid, int z0, int nz, const std::uint8_t* density, const std::uint8_t* theta,
                 const std::uint8_t* phi, std::vector<VoxelBrick>& out) {
    const glm::ivec3 d = grid.dims, bricks = (d + 7) / 8;
    const int layers = (nz + 7) / 8;
    // One list per brick column in x, joined in order afterwards.
    std::vector<std::vector<VoxelBrick>> perX(bricks.x);
    tbb::parallel_for(0, bricks.x, [&](int bx) {
        for (int by = 0; by < bricks.y; ++by)
            for (int lz = 0; lz < layers; ++lz) {
                VoxelBrick brick;
                bool any = false;
                for (int x = 0; x < 8; ++x)
                    for (int y = 0; y < 8; ++y)
                        for (int z = 0; z < 8; ++z) {
                            const int gx = bx * 8 + x, gy = by * 8 + y, sz = lz * 8 + z;
                            if (gx >= d.x || gy >= d.y || sz >= nz) continue;
                            const std::size_t i = (std::size_t(sz) * d.y + gy) * d.x + gx;
                            if (density[i] == 0) continue;
                            const int v = brickOffset(x, y, z);
                            brick.density[v] = density[i] / 255.0f;
                            brick.orientation[v] = decodeAngles(theta[i], phi[i]);
                            brick.activeMask[v >> 6] |= std::uint64_t(1) << (v & 63);
                            any = true;
                        }
                if (!any) continue;
                brick.key = brickKey({bx, by, z0 / 8 + lz});
                perX[bx].push_back(brick);
            }
    });
    for (auto& list : perX) out.insert(out.end(), list.begin(), list.end());
}

/// One pixel per (supersampled) voxel column of the whole grid: the
/// viewport's edge. Throws where the grid exceeds the method's limit (the
/// whole grid in one 3D texture per channel, all three resident at once) or
/// the viewport: checked before any work, so benchmarks can report "cannot
/// run" cheaply.
GLsizei denseViewport(const VoxelGrid& grid, int S, const GlContext& context) {
    const GlInfo& info = context.info();
    const glm::ivec3 dims = grid.dims;
    const std::uint64_t voxels = grid.voxelCount();
    const long long freeBytes = context.queryFreeMemoryBytes();
    const int maxSide = std::max({dims.x, dims.y, dims.z});
    const bool tooLarge = maxSide > info.max3dTextureSize || (freeBytes > 0 && 3 * voxels > std::uint64_t(freeBytes));
    if (tooLarge || dims.x <= 0 || dims.y <= 0 || dims.z <= 0)
        throw Error("dense method: grid " + dimsText(dims) + " exceeds one 3D texture (max " +
                    std::to_string(info.max3dTextureSize) + " per axis / " +
                    (freeBytes > 0 ? std::to_string(freeBytes >> 20) + " MiB free GPU memory" : std::string("GPU memory")) +
                    " for 3 textures of " + std::to_string(voxels >> 20) + " MiB)");
    GLint fbMax[2] = {0, 0}, viewportMax[2] = {0, 0};
    glGetIntegerv(GL_MAX_FRAMEBUFFER_WIDTH, &fbMax[0]);
    glGetIntegerv(GL_MAX_FRAMEBUFFER_HEIGHT, &fbMax[1]);
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, viewportMax);
    const long long viewport = (long long)maxSide * S;
    if (viewport > std::min({fbMax[0], fbMax[1], viewportMax[0], viewportMax[1]}))
        throw Error("dense method: grid " + dimsText(dims) + " at supersample " + std::to_string(S) +
                    " needs a " + std::to_string(viewport) + " pixel viewport, above this GPU's limit of " +
                    std::to_string(std::min({fbMax[0], fbMax[1], viewportMax[0], viewportMax[1]})));
    return GLsizei(viewport);
}

/// The plan's segments into `segments` and a draw list of every segment,
/// with its first instance, into `drawList`; returns the slices to draw.
std::uint64_t uploadDraw(const SlicePlan& plan, const VoxelGrid& grid, GlBuffer& segments, GlBuffer& drawList) {
    const GpuSegments packed = packSegments(plan, grid);
    segments.upload(packed.data(), packed.size() * sizeof(GpuSegment), nullptr);
    std::vector<std::uint32_t> draw(packed.size() * 2);
    std::uint64_t instances = 0;
    for (std::size_t i = 0; i < plan.segments.size(); ++i) {
        draw[2 * i] = static_cast<std::uint32_t>(i);
        draw[2 * i + 1] = static_cast<std::uint32_t>(instances);
        instances += plan.segments[i].sliceCount;
    }
    if (instances > 0x7fffffff)
        throw Error("dense method: " + std::to_string(instances) + " slices exceed one instanced draw");
    drawList.upload(draw.data(), draw.size() * 4, nullptr);
    return instances;
}

/// The three GL_R8 3D textures over the grid: density, theta, phi.
using DenseChannels = std::array<GlTexture, 3>;

DenseChannels allocateChannels(const VoxelGrid& grid) {
    const glm::ivec3 dims = grid.dims;
    glGetError(); // start the allocation check clean
    DenseChannels channels;
    for (GlTexture& t : channels) {
        t = createTexture(GL_TEXTURE_3D);
        glTextureStorage3D(t.id(), 1, GL_R8, dims.x, dims.y, dims.z);
    }
    if (glGetError() != GL_NO_ERROR)
        throw Error("dense method: grid " + dimsText(dims) + " exceeds one 3D texture (the driver cannot allocate 3 textures of " +
                    std::to_string(grid.voxelCount() >> 20) + " MiB)");
    return channels;
}

/// What the dense draw reads.
struct DenseDraw {
    const GlBuffer& segments;
    const GlBuffer& drawList;
    std::uint64_t instances;
    GLsizei viewport;
};

/// The slices placed once (slice_setup.comp, as the sparse backend does),
/// then drawn into `channels` (dense.frag); returns the draw's seconds.
double drawSlices(const SlicePlan& plan, const CrossSection& xs, const VoxelGrid& grid, TexelReads reads, int S,
                  const DenseDraw& draw, const GlTexture& crossSection, const DenseChannels& channels) {
    const SliceDraw sliceDraw{draw.segments.id(), draw.drawList.id(), static_cast<int>(plan.segments.size()),
                              plan.uniformSlices(), draw.instances};
    GlBuffer records;
    GlProgram program = GlProgram::graphics("slice.vert", "dense.frag", crossSectionDefines(xs, reads));
    const SlicePlacer placer;
    const GlVertexArray vao = createVertexArray();
    const GlFramebuffer fbo = createFramebuffer();
    glNamedFramebufferParameteri(fbo.id(), GL_FRAMEBUFFER_DEFAULT_WIDTH, draw.viewport);
    glNamedFramebufferParameteri(fbo.id(), GL_FRAMEBUFFER_DEFAULT_HEIGHT, draw.viewport);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
    glViewport(0, 0, draw.viewport, draw.viewport);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);

    const glm::ivec3 dims = grid.dims;
    program.use();
    glUniform1f(program.uniform("uRadius"), float(plan.options.radius / grid.voxelSize));
    glUniform1i(program.uniform("uSupersample"), S);
    glUniform1f(program.uniform("uSupport"), float(textureSupport(xs)));
    glUniform3i(program.uniform("uRegionMin"), 0, 0, 0);
    glUniform3i(program.uniform("uDims"), dims.x, dims.y, dims.z);
    glUniform2f(program.uniform("uViewport"), float(draw.viewport), float(draw.viewport));
    glBindTextureUnit(kCrossSectionUnit, crossSection.id());
    const GLuint images[3] = {GLuint(kDenseDensityImage), GLuint(kDenseThetaImage), GLuint(kDensePhiImage)};
    for (int i = 0; i < 3; ++i)
        glBindImageTexture(images[i], channels[i].id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_R8);
    glBindVertexArray(vao.id());
    double seconds = 0.0;
    if (draw.instances > 0)
        seconds = timedGpu([&] {
            placer.place(sliceDraw, records, nullptr);
            program.use();
            records.bindStorage(kSlicesBinding);
            glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, kSliceVertices, static_cast<GLsizei>(draw.instances));
        });
    checkGlError("dense raster pass");
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    return seconds;
}

/// The channels read back slab by slab in z (whole brick layers, about 256
/// MiB of host memory for the three channels), so big grids do not need 3
/// bytes per voxel on the host as well, and turned into bricks.
BrickVolume readChannels(const VoxelGrid& grid, const DenseChannels& channels) {
    const glm::ivec3 dims = grid.dims;
    const std::uint64_t layerBytes = std::uint64_t(dims.x) * dims.y * 8;
    const int slabDepth = int(std::clamp<std::uint64_t>((std::uint64_t(256) << 20) / (3 * layerBytes), 1, (dims.z + 7) / 8)) * 8;
    std::vector<std::uint8_t> slab[3];
    BrickVolume volume;
    volume.grid = grid;
    volume.reduce = Reduce::Max;
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    for (int z0 = 0; z0 < dims.z; z0 += slabDepth) {
        const int nz = std::min(slabDepth, dims.z - z0);
        const std::size_t bytes = std::size_t(dims.x) * dims.y * nz;
        // Each call's buffer size is a GLsizei: calls of at most 1 GiB.
        const std::size_t sliceBytes = std::size_t(dims.x) * dims.y;
        const int chunk = int(std::max<std::size_t>(1, (std::size_t(1) << 30) / sliceBytes));
        for (int k = 0; k < 3; ++k) {
            slab[k].resize(bytes);
            for (int z = 0; z < nz; z += chunk) {
                const int n = std::min(chunk, nz - z);
                glGetTextureSubImage(channels[k].id(), 0, 0, 0, z0 + z, dims.x, dims.y, n, GL_RED, GL_UNSIGNED_BYTE,
                                     static_cast<GLsizei>(sliceBytes * n), slab[k].data() + sliceBytes * z);
            }
        }
        checkGlError("reading back the 3D textures");
        convertSlab(grid, z0, nz, slab[0].data(), slab[1].data(), slab[2].data(), volume.bricks);
    }
    std::sort(volume.bricks.begin(), volume.bricks.end(),
              [](const VoxelBrick& a, const VoxelBrick& b) { return a.key < b.key; });
    for (const VoxelBrick& b : volume.bricks)
        for (int v = 0; v < kBrickVoxels; ++v)
            if (b.isActive(v)) {
                ++volume.tally.activeVoxels;
                volume.tally.densitySum += b.density[v];
            }
    volume.tally.rawDensitySum = volume.tally.densitySum;
    return volume;
}

} // namespace

JsonObject toJson(const DenseVoxelizeCounters& counters) {
    JsonObject out;
    out.set("renderer", counters.renderer)
        .set("platform", counters.platform)
        .set("method", "dense")
        .set("gpu_peak_bytes", counters.textureBytes)
        .set("slices_drawn", counters.instances)
        .set("gpu_clear_seconds", counters.clearSeconds)
        .set("gpu_raster_seconds", counters.rasterSeconds)
        .set("readback_seconds", counters.readbackSeconds);
    return out;
}

BrickVolume voxelizeDense(const SlicePlan& plan, const CrossSection& xs, const VoxelGrid& grid,
                          const GlVoxelizeSettings& settings, const GlContext& context,
                          DenseVoxelizeCounters* counters) {
    if (xs.hasAlbedo()) throw Error("--albedo: the dense method has no albedo; use --method sparse");
    DenseVoxelizeCounters local;
    DenseVoxelizeCounters& c = counters ? *counters : local;
    const int S = settings.base.supersample;
    checkSupersample(S);
    context.makeCurrent();
    c.renderer = context.info().renderer;
    c.platform = platformName(context.info().platform);

    const GLsizei viewport = denseViewport(grid, S, context);
    GlBuffer segments, drawList;
    c.instances = uploadDraw(plan, grid, segments, drawList);
    const TexelReads reads = texelReadsFor(settings.texelReads);
    const GlTexture crossSection = uploadCrossSectionTexture(xs, reads);
    checkGlError("uploading segments and the cross-section");

    const DenseChannels channels = allocateChannels(grid);
    c.textureBytes = 3 * grid.voxelCount();
    c.clearSeconds = timedGpu([&] {
        const std::uint8_t zero = 0;
        for (const GlTexture& t : channels) glClearTexImage(t.id(), 0, GL_RED, GL_UNSIGNED_BYTE, &zero);
    });
    checkGlError("clearing the 3D textures");
    c.rasterSeconds = drawSlices(plan, xs, grid, reads, S, DenseDraw{segments, drawList, c.instances, viewport},
                                 crossSection, channels);

    const auto readStart = std::chrono::steady_clock::now();
    BrickVolume volume = readChannels(grid, channels);
    c.readbackSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - readStart).count();
    return volume;
}

} // namespace yv

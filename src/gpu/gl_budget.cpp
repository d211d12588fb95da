#include "gpu/gl_budget.h"

#include "core/error.h"
#include "gpu/brick_resolver.h"
#include "gpu/gpu_layout.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace yv {

SliceDrawing chooseSliceDrawing(const GlVoxelizeSettings& settings, const SlicePlan& plan, const VoxelGrid& grid,
                                double support, const GlInfo& info) {
    SliceDrawing drawing;
    const SlicePrimitive asked = settings.slicePrimitive;
    if (asked == SlicePrimitive::Compute || asked == SlicePrimitive::Auto) {
        drawing.compute = true;
        return drawing;
    }
    if (asked == SlicePrimitive::Triangle || (asked != SlicePrimitive::Point && !info.hardware())) return drawing;
    const double S = settings.base.supersample, r = plan.options.radius / grid.voxelSize;
    // Runs of slices, one sprite each, where the yarn is thin on the face:
    // there a point's fixed cost is most of its time, and two slices'
    // sprites cover nearly the same few pixels (slice_runs.comp).
    if (settings.sliceRun < 0 || settings.sliceRun > kSliceRunLimit)
        throw Error("a point sprite draws 1 to " + std::to_string(kSliceRunLimit) + " slices (asked for " +
                    std::to_string(settings.sliceRun) + ")");
    int runSlices = 1;
    if (settings.sliceRun > 0)
        runSlices = settings.sliceRun;
    else
        runSlices = support * r * S < kSliceRunSupportPixels ? kSliceRunMax : 1;
    GLfloat sizes[2] = {0, 0};
    glGetFloatv(GL_POINT_SIZE_RANGE, sizes);
    // A bound on slice.vert's reach: its footprint term (a share of the
    // footprint's longer diagonal) is at most half the edges' sum, at most
    // sqrt(3)/S since 1/|tangent[a]| <= sqrt(3); and the square's corners.
    // A run's sprite is at most half the spread of its slices' centres
    // wider than its widest slice's; where runs' sprites would not fit the
    // driver's point sizes, a slice's may.
    const double reach = (support * r + 1.75 / S) * 1.001 + 0.05 / S, extent = r + 2.0 / S;
    const auto halfPixelsWith = [&](int slices) {
        return std::max(reach, extent * std::sqrt(2.0)) * S + 0.05 + (slices > 1 ? 0.5 * kSliceRunSpread : 0.0);
    };
    if (runSlices > 1 && !(2.0 * halfPixelsWith(runSlices) + 1.0 <= sizes[1])) runSlices = 1;
    const double halfPixels = halfPixelsWith(runSlices);
    if (!(2.0 * halfPixels + 1.0 <= sizes[1])) return drawing;
    drawing.pointMargin = static_cast<int>(std::ceil(halfPixels)) + 2; // chooseBudget keeps regions within the rest
    drawing.runSlices = runSlices;
    return drawing;
}

GlBudget chooseBudget(const GlVoxelizeSettings& settings, const SlicePlan& plan, const VoxelGrid& grid,
                      const GlContext& context, const SliceDrawing& drawing, int words, bool albedo) {
    const GlInfo& info = context.info();
    GlBudget budget;
    // Every buffer is bound whole as one shader storage block, so none may
    // exceed GL_MAX_SHADER_STORAGE_BLOCK_SIZE; together they stay within
    // half of the free GPU memory where the driver reports it.
    const std::uint64_t block = static_cast<std::uint64_t>(std::max<long long>(info.maxSsboBlockSize, 1 << 20));
    const long long freeBytes = context.queryFreeMemoryBytes();
    const std::uint64_t memory = freeBytes > 0 ? static_cast<std::uint64_t>(freeBytes) / 2 : (std::uint64_t(1) << 30);
    // A unit of the budget is a fragment (with albedo a second record as
    // large, GpuAlbedoFragment) and a sample item: the item list holds
    // as many items as the fragment list holds fragments.
    const std::uint64_t unitBytes = sizeof(GpuFragment) * (albedo ? 2 : 1) + sizeof(GpuSampleItem);
    std::uint64_t capacity = settings.fragmentCapacity ? settings.fragmentCapacity : memory / 2 / unitBytes;
    capacity = std::min<std::uint64_t>(capacity, block / sizeof(GpuFragment));
    budget.maxBlock = block;
    // Slots at 2^31 and beyond flag the pass as overflowed (append.frag).
    budget.capacity = capacity = std::min<std::uint64_t>(capacity, 0x7fffffffu);
    // A brick slot holds its words, and the resolve's output for it in the worst case.
    const std::uint64_t wordBytes = std::uint64_t(words) * kBrickVoxels * 4;
    const std::uint64_t resolveBytes = resolveBytesPerBrick(albedo);
    budget.brickBudget = std::min(block / std::max(wordBytes, resolveBytes), memory / 3 / (wordBytes + resolveBytes));
    if (settings.fragmentCapacity)
        budget.brickBudget = std::min<std::uint64_t>(budget.brickBudget, std::max<std::uint64_t>(capacity / 8, 1));

    GLint fbMax[2] = {0, 0}, viewportMax[2] = {0, 0};
    glGetIntegerv(GL_MAX_FRAMEBUFFER_WIDTH, &fbMax[0]);
    glGetIntegerv(GL_MAX_FRAMEBUFFER_HEIGHT, &fbMax[1]);
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, viewportMax);
    // Point sprites take a margin around the region's face (chooseSliceDrawing).
    const int pixels = std::min({fbMax[0], fbMax[1], viewportMax[0], viewportMax[1]}) - 2 * drawing.pointMargin;
    // Region keys hold a brick index in 23 bits: at most 2^23 bricks a region.
    budget.regionCap = std::min(1024, (pixels / settings.base.supersample) / 8 * 8);
    budget.maxGroups = static_cast<GLuint>(std::min(info.maxComputeWorkGroupCountX, 65535));

    // The smallest piece of work is one segment over one brick.
    budget.uniformSlices = plan.uniformSlices();
    // Each sample's slab column is split over at most this many voxels
    // (and over at most 8 of one brick).
    const double slabDepth = 2.0 * std::max(0.0, plan.maxReach - plan.options.radius * std::sqrt(2.0)) / grid.voxelSize;
    const std::uint64_t pieces = std::min<std::uint64_t>(8, 2 + static_cast<std::uint64_t>(slabDepth));
    const std::uint64_t worst = std::uint64_t(plan.mostSlices) * 64 * settings.base.supersample * settings.base.supersample * pieces;
    if (capacity < worst)
        throw Error("fragment budget " + std::to_string(capacity) + " is below the " + std::to_string(worst) +
                    " fragments one segment can put into one brick; raise --fragment-budget");
    if (settings.verbose)
        std::fprintf(stderr, "gl: %s, %s; ssbo block %lld MiB, free %lld MiB; capacity %llu fragments, %llu bricks, regions <= %d\n",
                     info.renderer.c_str(), info.version.c_str(), info.maxSsboBlockSize >> 20,
                     freeBytes > 0 ? freeBytes >> 20 : -1LL, static_cast<unsigned long long>(capacity),
                     static_cast<unsigned long long>(budget.brickBudget), budget.regionCap);
    return budget;
}

} // namespace yv

#include "gpu/raster_pass.h"

#include "core/trace.h"
#include "gpu/gl_bindings.h"
#include "gpu/gpu_layout.h"

#include <algorithm>
#include <utility>

namespace yv {
namespace {

/// The raster's variant: the cross-section's, and with point sprites their runs' length.
std::vector<std::string> rasterDefines(std::vector<std::string> defines, const SliceDrawing& drawing) {
    // The raster bounds a footprint by what the sampling reads of it (the
    // disk's whole footprint, or a texture's cell centres: slice.vert).
    if (drawing.points()) {
        defines.push_back("SLICE_POINTS 1");
        defines.push_back("SLICE_RUN " + std::to_string(drawing.runSlices));
    }
    return defines;
}

/// The pass's program: the raster's, or its compute stand-in's.
GlProgram itemProgram(const SliceDrawing& drawing, std::vector<std::string> defines) {
    if (drawing.compute) return GlProgram::compute("slice_items.comp", defines);
    return GlProgram::graphics("slice.vert", "append.frag", rasterDefines(std::move(defines), drawing));
}

} // namespace

RasterPass::RasterPass(const SlicePlan& plan, const GlBuffer& segments, const SliceDrawing& drawing,
                       const GlBudget& budget, std::vector<std::string> defines, bool timerQueries,
                       std::uint64_t* gpuBytes)
    : plan_(plan), segments_(segments), drawing_(drawing), uniformSlices_(budget.uniformSlices),
      maxBlock_(budget.maxBlock), maxGroups_(budget.maxGroups), gpuBytes_(gpuBytes),
      placer_(drawing.runSlices, rasterDefines(defines, drawing)),
      program_(itemProgram(drawing, std::move(defines))),
      vao_(createVertexArray()), fbo_(createFramebuffer()), placeTimer_(timerQueries), drawTimer_(timerQueries) {
    runDraw_.reserve(16, gpuBytes_); // with point sprites, the draw's command (its first word: the runs)
    runDraw_.clear(16);
}

std::optional<std::uint64_t> RasterPass::run(const WorkItem& item, const SamplingUniforms& uniforms,
                                             SampleLists& lists) {
    // Draw list: segment index and the first instance of each.
    std::vector<std::uint32_t> drawList(item.segments.size() * 2);
    std::uint64_t instances = 0;
    for (std::size_t i = 0; i < item.segments.size(); ++i) {
        drawList[2 * i] = item.segments[i];
        drawList[2 * i + 1] = static_cast<std::uint32_t>(instances);
        instances += plan_.segments[item.segments[i]].sliceCount;
    }
    if (instances > 0x7fffffff || instances * sizeof(GpuSliceRecord) > maxBlock_) return std::nullopt;
    drawList_.upload(drawList.data(), drawList.size() * 4, gpuBytes_);
    lists.resetCounters();

    // The slices placed on every compute unit, then drawn.
    placeTimer_.begin();
    {
        const TraceSpan placing("place the slices");
        placer_.place(SliceDraw{segments_.id(), drawList_.id(), static_cast<int>(item.segments.size()), uniformSlices_,
                                instances},
                      slices_, gpuBytes_);
        if (drawing_.runSlices > 1)
            placer_.joinRuns(instances, uniforms.supersample, kSliceRunSpread, slices_, runs_, runDraw_, gpuBytes_);
    }
    placeTimer_.end();
    if (drawing_.compute)
        appendInCompute(uniforms, item, lists, instances);
    else
        draw(item, uniforms, lists, instances);
    return instances;
}

void RasterPass::appendInCompute(const SamplingUniforms& uniforms, const WorkItem& item, const SampleLists& lists,
                                 std::uint64_t instances) {
    drawTimer_.begin();
    const TraceSpan appending("append the sample items");
    program_.use();
    uniforms.set(program_, item);
    glUniform1ui(program_.uniform("uItemCapacity"), static_cast<GLuint>(lists.itemSlots()));
    glUniform1ui(program_.uniform("uInstances"), static_cast<GLuint>(instances));
    slices_.bindStorage(kSlicesBinding);
    lists.items().bindStorage(kItemsBinding);
    lists.itemCounter().bindStorage(kItemCounterBinding);
    const std::uint64_t groups = (instances + kItemGroupSize - 1) / kItemGroupSize;
    if (groups > 0) glDispatchCompute(static_cast<GLuint>(std::min<std::uint64_t>(groups, maxGroups_)), 1, 1);
    drawTimer_.end();
    checkGlError("sample items in compute");
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_ATOMIC_COUNTER_BARRIER_BIT);
}

void RasterPass::draw(const WorkItem& item, const SamplingUniforms& uniforms, const SampleLists& lists,
                      std::uint64_t instances) {
    drawTimer_.begin();
    // Submitting the draw (the driver may wait here on first use).
    const TraceSpan drawing("draw the slices");
    const glm::ivec3 size = item.max - item.min;
    const int viewport = std::max({size.x, size.y, size.z}) * uniforms.supersample + 2 * drawing_.pointMargin;
    glNamedFramebufferParameteri(fbo_.id(), GL_FRAMEBUFFER_DEFAULT_WIDTH, viewport);
    glNamedFramebufferParameteri(fbo_.id(), GL_FRAMEBUFFER_DEFAULT_HEIGHT, viewport);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
    glViewport(0, 0, viewport, viewport);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);

    program_.use();
    uniforms.set(program_, item);
    glUniform2f(program_.uniform("uViewport"), float(viewport), float(viewport));
    glUniform1i(program_.uniform("uMargin"), drawing_.pointMargin);
    glUniform1ui(program_.uniform("uItemCapacity"), static_cast<GLuint>(lists.itemSlots()));
    slices_.bindStorage(kSlicesBinding);
    lists.items().bindStorage(kItemsBinding);
    lists.itemCounter().bindStorage(kItemCounterBinding); // the wrap flag
    glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, kItemCountAtomic, lists.itemCounter().id());
    glBindVertexArray(vao_.id());
    if (drawing_.runSlices > 1) {
        // Vertex i is run i; their count is on the GPU (slice_runs.comp).
        glEnable(GL_PROGRAM_POINT_SIZE);
        runs_.bindStorage(kRunsBinding);
        glBindBuffer(GL_DRAW_INDIRECT_BUFFER, runDraw_.id());
        glDrawArraysIndirect(GL_POINTS, nullptr);
        glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    } else if (drawing_.points()) {
        glEnable(GL_PROGRAM_POINT_SIZE);
        glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(instances)); // vertex i is slice i
    } else {
        glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, kSliceVertices, static_cast<GLsizei>(instances));
    }
    drawTimer_.end();
    checkGlError("raster pass");
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_ATOMIC_COUNTER_BARRIER_BIT);
}

} // namespace yv

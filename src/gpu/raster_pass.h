// The GL backend's first pass over a work item: its slices placed on the GPU
// (slice_placer.h), then drawn over the item's face, as triangles or point
// sprites (slice.vert), and one sample item appended per pixel that can hold
// fibre (append.frag); or, in place of the draw, the same items appended by
// a compute pass (slice_items.comp).
#pragma once

#include "garment/slices.h"
#include "gpu/gl_budget.h"
#include "gpu/gl_buffer.h"
#include "gpu/gl_objects.h"
#include "gpu/gl_program.h"
#include "gpu/gpu_timer.h"
#include "gpu/sample_lists.h"
#include "gpu/slice_placer.h"
#include "gpu/work_item.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace yv {

class RasterPass {
  public:
    /// Draws the slices of `segments` (the plan's, packed: GpuSegment) as
    /// `drawing` says; `defines`: the cross-section's variant
    /// (crossSectionDefines). `gpuBytes` tracks its buffers.
    RasterPass(const SlicePlan& plan, const GlBuffer& segments, const SliceDrawing& drawing, const GlBudget& budget,
               std::vector<std::string> defines, bool timerQueries, std::uint64_t* gpuBytes);

    /// Places and draws the slices of `item`'s segments, their sample items
    /// appended to `lists` (whose counters it resets first). Returns the
    /// slices drawn, or nothing (and draws nothing) when they exceed one draw.
    std::optional<std::uint64_t> run(const WorkItem& item, const SamplingUniforms& uniforms, SampleLists& lists);

    /// The placed slices (GpuSliceRecord per instance), for the sampling.
    const GlBuffer& slices() const { return slices_; }
    /// The runs' draw command: its first word is the runs drawn (0 without runs).
    const GlBuffer& runDraw() const { return runDraw_; }
    /// GPU seconds of placing the slices, and of drawing them.
    double placeSeconds() { return placeTimer_.seconds(); }
    double drawSeconds() { return drawTimer_.seconds(); }

  private:
    void draw(const WorkItem& item, const SamplingUniforms& uniforms, const SampleLists& lists, std::uint64_t instances);
    void appendInCompute(const SamplingUniforms& uniforms, const WorkItem& item, const SampleLists& lists,
                         std::uint64_t instances);

    /// slice_items.comp's local size.
    static constexpr std::uint64_t kItemGroupSize = 256;

    const SlicePlan& plan_;
    const GlBuffer& segments_;
    SliceDrawing drawing_;
    std::uint32_t uniformSlices_;
    std::uint64_t maxBlock_;
    GLuint maxGroups_; ///< work groups of one dispatch (GlBudget::maxGroups)
    std::uint64_t* gpuBytes_;
    SlicePlacer placer_;
    GlProgram program_;
    GlVertexArray vao_;
    GlFramebuffer fbo_;
    GlBuffer drawList_; ///< per segment drawn: its index and its first instance
    GlBuffer slices_, runs_, runDraw_;
    GpuTimer placeTimer_, drawTimer_;
};

} // namespace yv

// Places the slices of one draw on the GPU before the draw
// (shaders/slice_setup.comp): one SliceRecord per instance, which the
// sprite's vertex shader and the sampling pass read; for point sprites, then
// joins them into runs that one sprite draws (shaders/slice_runs.comp).
#pragma once

#include "gpu/gl_buffer.h"
#include "gpu/gl_program.h"

#include <epoxy/gl.h>

#include <cstdint>
#include <string>
#include <vector>

namespace yv {

/// The draw's inputs: segments (GpuSegment) and its draw list (segment index
/// and first instance of each entry).
struct SliceDraw {
    GLuint segments = 0, drawList = 0;
    int drawCount = 0;                 ///< entries in the draw list
    std::uint32_t uniformSlices = 0;   ///< slices of every segment when all agree, else 0
    std::uint64_t instances = 0;
};

class SlicePlacer {
  public:
    /// `runSlices`: slices a run holds at most (0 or 1: no runs).
    /// `runDefines`: the raster's defines (the run length among them).
    explicit SlicePlacer(int runSlices = 0, const std::vector<std::string>& runDefines = {});
    /// Writes the draw's records into `records` (grown to fit; `gpuBytes`
    /// tracks it) and orders them before later shader reads.
    void place(const SliceDraw& draw, GlBuffer& records, std::uint64_t* gpuBytes) const;
    /// Joins the `instances` records into runs of consecutive slices with one
    /// projection axis whose centres lie within `spread` pixels of each other
    /// on the face: GpuSliceRun entries into `runs` (grown to fit), and their
    /// count into `command`, a glDrawArraysIndirect command (16 bytes), both
    /// ordered before the draw.
    void joinRuns(std::uint64_t instances, int supersample, float spread, const GlBuffer& records, GlBuffer& runs,
                  GlBuffer& command, std::uint64_t* gpuBytes) const;

  private:
    GlProgram program_, runs_;
    GlBuffer commandStart_; ///< the command before the runs: (0, 1, 0, 0)
    int runSlices_ = 0;
    GLuint maxGroups_ = 65535;
};

} // namespace yv

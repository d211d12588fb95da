// Places the slices of one instanced draw on the GPU before the draw
// (shaders/slice_setup.comp): one SliceRecord per instance, which the
// sprite's vertex shader and the sampling pass read.
#pragma once

#include "gpu/gl_buffer.h"
#include "gpu/gl_program.h"

#include <epoxy/gl.h>

#include <cstdint>

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
    SlicePlacer();
    /// Writes the draw's records into `records` (grown to fit; `gpuBytes`
    /// tracks it) and orders them before later shader reads.
    void place(const SliceDraw& draw, GlBuffer& records, std::uint64_t* gpuBytes) const;

  private:
    GlProgram program_;
    GLuint maxGroups_ = 65535;
};

} // namespace yv

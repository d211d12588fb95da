// The exclusive prefix sum of an array of 32-bit counts on the GPU, in
// place (radix_scan.comp: three passes, the sums of blocks of 1024 counts
// scanned by one work group between them), optionally with the total
// written to a buffer's first word. The radix sort scans its histograms
// with it, the slices' tiles their counts. Nothing is read back; the
// context must be current.
#pragma once

#include "gpu/gl_buffer.h"
#include "gpu/gl_program.h"

#include <cstdint>

namespace yv {

class GpuScan {
  public:
    /// Room for scans of up to `capacity` counts; `maxGroups`: the work groups a dispatch may have.
    GpuScan(std::uint64_t capacity, GLuint maxGroups);

    /// Makes room for scans of up to `capacity` counts (never shrinks).
    void reserve(std::uint64_t capacity);
    /// Replaces the first `count` words of `counts` by the sum of the words
    /// before each; writes their total to word 0 of `total` where given.
    /// Queued on the GPU (barriers included).
    void run(const GlBuffer& counts, std::uint32_t count, const GlBuffer* total);

  private:
    GLuint maxGroups_;
    GlProgram program_;
    GlBuffer blockSums_;
};

} // namespace yv

// The GL backend's third pass over a work item: its fragments gathered into
// bricks. Every brick of the item that a fragment touches is flagged
// (brick_flag.comp), the flags scanned into slots (brick_scan.comp), and
// each fragment added into its slot's words (brick_scatter.comp; with
// --reduce max, brick_max_orient.comp then picks each voxel's axis).
#pragma once

#include "core/bricks.h"
#include "gpu/gl_buffer.h"
#include "gpu/gl_program.h"
#include "gpu/gpu_timer.h"
#include "gpu/sample_lists.h"
#include "gpu/work_item.h"

#include <cstdint>
#include <optional>

namespace yv {

class BrickPass {
  public:
    /// `reduce` and `albedo` pick the scatter's variant and the words a
    /// voxel has (wordsPerVoxel). `gpuBytes` tracks its buffers.
    BrickPass(Reduce reduce, bool albedo, GLuint maxGroups, bool timerQueries, std::uint64_t* gpuBytes);

    /// Builds the bricks of the `fragments` fragments in `lists` over `item`.
    /// Returns the touched bricks (slots), or nothing when they are more
    /// than `brickBudget` (the item is then split). Waits for the count.
    std::optional<GLuint> build(const WorkItem& item, GLuint fragments, const SampleLists& lists, ReadbackBuffer& small,
                                std::uint64_t brickBudget);

    /// Per slot, wordsPerVoxel channels of 512 words (as BrickAccumulator).
    const GlBuffer& words() const { return brickWords_; }
    /// Per slot, its brick's index in the item (x fastest).
    const GlBuffer& slotBricks() const { return slotBricks_; }
    /// GPU seconds of the brick passes so far.
    double seconds() { return timer_.seconds(); }

  private:
    /// Zeroes the first `bytes` (a multiple of 4) of `buffer` with a dispatch
    /// (see buffer_clear.comp for why not glClearNamedBufferSubData).
    void zero(const GlBuffer& buffer, std::uint64_t bytes);
    GLuint groupsFor(std::uint64_t threads) const;
    void scatter(GLuint fragments, const SampleLists& lists);

    Reduce reduce_;
    bool albedo_;
    int wordsPerVoxel_;
    GLuint maxGroups_;
    std::uint64_t* gpuBytes_;
    GlProgram flag_, clear_, scan_, scatter_, maxOrient_;
    GlBuffer flags_, blockSums_, counts_, slotBricks_, brickWords_;
    GpuTimer timer_;
};

} // namespace yv

// The GL backend's last pass over a work item: its bricks brought to the
// host. Resolved on the GPU and copied back packed (brick_resolver.h), the
// copy taken in while the next pass runs; or, for a brick drawn in several
// passes and for every brick with the host resolve, read back raw and summed
// into the region's accumulators.
#pragma once

#include "core/bricks.h"
#include "core/packed_bricks.h"
#include "gpu/brick_pass.h"
#include "gpu/brick_resolver.h"
#include "gpu/gl_buffer.h"
#include "gpu/work_item.h"

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace yv {

class BrickReadback {
  public:
    /// `small`: the backend's buffer for reads of a few bytes (shared with
    /// the other passes). `gpuBytes` tracks the buffers.
    BrickReadback(Reduce reduce, Overlap overlap, bool albedo, ReadbackBuffer& small, std::uint64_t* gpuBytes);

    /// Resolves the `activeBricks` slots that `bricks` built over `item` on
    /// the GPU (the pass's `fragments` bound its active voxels) and queues
    /// the copy of the packed bricks, which takeInPassBefore() appends to
    /// `target`; `target` must stay where it is until then.
    void startPacked(const WorkItem& item, const BrickPass& bricks, GLuint activeBricks, GLuint fragments,
                     PackedBricks& target);
    /// Appends the packed bricks still on their way to the region they
    /// belong to (waits for their copy); nothing when none are.
    void takeInPassBefore();

    /// Reads back the raw words of the `activeBricks` slots and adds each to
    /// the region's accumulator of its brick. Returns the bricks added to an
    /// accumulator already there (drawn in an earlier pass).
    std::uint64_t readRaw(const WorkItem& item, const BrickPass& bricks, GLuint activeBricks);
    bool hasAccumulators() const { return !accumulators_.empty(); }
    /// The region's accumulators, sorted by key (none are left).
    std::vector<BrickAccumulator> takeAccumulators();
    /// Resolves the region's accumulators on the GPU and appends them to
    /// `out`, in the order they came (none are left).
    void resolveAccumulators(PackedBricks& out);

    /// The GPU's resolve time, until the totals are on the host.
    double resolveSeconds() const { return resolver_.gpuSeconds(); }
    /// Wall time of reading back bricks (packed, and raw ones).
    double readbackSeconds() const { return rawReadSeconds_ + resolver_.readbackSeconds(); }
    /// Bytes copied from the GPU to the host for the bricks.
    std::uint64_t bytesRead() const { return raw_.bytesRead() + resolver_.bytesRead(); }

  private:
    Reduce reduce_;
    bool albedo_;
    ReadbackBuffer& small_;
    std::uint64_t* gpuBytes_;
    GlBrickResolver resolver_;
    PackedBricks* pendingTarget_ = nullptr; ///< where the resolve in flight appends
    ReadbackBuffer raw_;                    ///< the raw words' copy
    /// The current region's raw bricks: those drawn in several passes, or
    /// all of them with the host resolve.
    std::vector<BrickAccumulator> accumulators_;
    std::unordered_map<std::uint64_t, std::size_t> slotOfKey_; ///< key -> index in accumulators_
    double rawReadSeconds_ = 0.0;
};

} // namespace yv

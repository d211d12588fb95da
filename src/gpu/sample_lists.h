// The lists a pass appends to: the raster's sample items and the sampling's
// fragments (with --albedo their colours), each behind a 32-bit counter.
#pragma once

#include "gpu/gl_buffer.h"

#include <epoxy/gl.h>

#include <cstdint>

namespace yv {

/// The counts a pass left on the GPU, read once its passes are done.
struct PassCounts {
    GLuint fragments = 0, items = 0;
    /// A counter went past 2^31 (and may have wrapped to a small count), far
    /// beyond any list: the pass is redone in pieces.
    bool wrapped = false;
    GLuint runs = 0; ///< point sprites drawn (slice_runs.comp; 0 without runs)
};

/// The sample item and fragment lists with their counters. They start small
/// and grow, up to `capacity` slots, to what a pass needs, so that a small
/// garment does not hold the whole budget on the GPU.
class SampleLists {
  public:
    /// `initialSlots`: the slots both lists start with (0: 2^20).
    /// `counterStart`, `itemCounterStart`: where the first pass's counters
    /// start (tests make them wrap). `gpuBytes` tracks the buffers.
    SampleLists(std::uint64_t capacity, std::uint64_t initialSlots, bool albedo, std::uint32_t counterStart,
                std::uint32_t itemCounterStart, std::uint64_t* gpuBytes);

    /// Both lists at least `slots` long (within the capacity).
    void reserveAtLeast(std::uint64_t slots);
    /// The item list for `items` and a quarter more (within the capacity).
    void growItems(GLuint items);
    /// The fragment list likewise.
    void growFragments(GLuint fragments);

    /// Both counters to zero before a pass (the first pass's to their starts).
    void resetCounters();
    /// The fragment counter alone, before the sampling is redone.
    void resetFragmentCounter() { fragmentCounter_.clear(8); }
    /// The counters and their wrap flags, and the runs' count, the first
    /// word of `runDraw` (RasterPass::runDraw()), once the passes before are done.
    PassCounts read(ReadbackBuffer& small, const GlBuffer& runDraw);

    std::uint64_t capacity() const { return capacity_; }
    std::uint64_t fragmentSlots() const { return fragmentSlots_; }
    std::uint64_t itemSlots() const { return itemSlots_; }
    const GlBuffer& fragments() const { return fragments_; }
    const GlBuffer& albedoFragments() const { return albedoFragments_; }
    const GlBuffer& items() const { return items_; }
    /// The fragment count (an atomic counter), then its wrap flag.
    const GlBuffer& fragmentCounter() const { return fragmentCounter_; }
    /// The item count (an atomic counter), its wrap flag, then the sampling's dispatch size.
    const GlBuffer& itemCounter() const { return itemCounter_; }

  private:
    void reserve();

    std::uint64_t capacity_;
    bool albedo_;
    std::uint64_t* gpuBytes_;
    std::uint32_t counterStart_, itemCounterStart_;
    std::uint64_t fragmentSlots_ = 0, itemSlots_ = 0;
    GlBuffer fragments_, albedoFragments_, items_, fragmentCounter_, itemCounter_;
};

} // namespace yv

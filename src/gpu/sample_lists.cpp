#include "gpu/sample_lists.h"

#include "core/trace.h"
#include "gpu/gpu_layout.h"

#include <algorithm>
#include <cstring>
#include <utility>

namespace yv {
namespace {
constexpr std::uint64_t kInitialSlots = 1 << 20; // 16 MiB of fragments, 8 MiB of sample items
}

SampleLists::SampleLists(std::uint64_t capacity, std::uint64_t initialSlots, bool albedo, std::uint32_t counterStart,
                         std::uint32_t itemCounterStart, std::uint64_t* gpuBytes)
    : capacity_(capacity), albedo_(albedo), gpuBytes_(gpuBytes), counterStart_(counterStart),
      itemCounterStart_(itemCounterStart) {
    fragmentSlots_ = itemSlots_ = std::min<std::uint64_t>(capacity_, initialSlots ? initialSlots : kInitialSlots);
    reserve();
    fragmentCounter_.reserve(8, gpuBytes_); // the counter, then the flag of a counter that wrapped
    itemCounter_.reserve(32, gpuBytes_);    // likewise, then the sampling pass's dispatch size
}

void SampleLists::reserve() {
    fragments_.reserve(fragmentSlots_ * sizeof(GpuFragment), gpuBytes_);
    if (albedo_) albedoFragments_.reserve(fragmentSlots_ * sizeof(GpuAlbedoFragment), gpuBytes_);
    items_.reserve(itemSlots_ * sizeof(GpuSampleItem), gpuBytes_);
}

void SampleLists::reserveAtLeast(std::uint64_t slots) {
    slots = std::min(capacity_, slots);
    fragmentSlots_ = std::max(fragmentSlots_, slots);
    itemSlots_ = std::max(itemSlots_, slots);
    reserve();
}

void SampleLists::growItems(GLuint items) {
    itemSlots_ = std::min<std::uint64_t>(capacity_, std::uint64_t(items) + items / 4);
    reserve();
}

void SampleLists::growFragments(GLuint fragments) {
    fragmentSlots_ = std::min<std::uint64_t>(capacity_, std::uint64_t(fragments) + fragments / 4);
    reserve();
}

void SampleLists::resetCounters() {
    fragmentCounter_.clear(8);
    itemCounter_.clear(32);
    if (const std::uint32_t start = std::exchange(counterStart_, 0); start != 0)
        glNamedBufferSubData(fragmentCounter_.id(), 0, 4, &start);
    if (const std::uint32_t start = std::exchange(itemCounterStart_, 0); start != 0)
        glNamedBufferSubData(itemCounter_.id(), 0, 4, &start);
}

PassCounts SampleLists::read(ReadbackBuffer& small, const GlBuffer& runDraw) {
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_ATOMIC_COUNTER_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    const TraceSpan span("wait for the fragment count");
    // Each counter, then its wrap flag; then the runs drawn.
    GLuint words[5] = {0, 0, 0, 0, 0};
    std::memcpy(words,
                small.read({{fragmentCounter_.id(), 0, 8}, {itemCounter_.id(), 0, 8}, {runDraw.id(), 0, 4}}, gpuBytes_),
                20);
    return PassCounts{words[0], words[2], words[1] != 0 || words[3] != 0, words[4]};
}

} // namespace yv

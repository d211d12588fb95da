#include "gpu/brick_readback.h"

#include "core/sampling.h"
#include "core/trace.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <utility>

namespace yv {

BrickReadback::BrickReadback(Reduce reduce, Overlap overlap, bool albedo, ReadbackBuffer& small,
                             std::uint64_t* gpuBytes)
    : reduce_(reduce), albedo_(albedo), small_(small), gpuBytes_(gpuBytes),
      resolver_(reduce, overlap, gpuBytes, albedo) {}

void BrickReadback::startPacked(const WorkItem& item, const BrickPass& bricks, GLuint activeBricks, GLuint fragments,
                                PackedBricks& target) {
    // The host waits for the resolved totals only (a few bytes); the copy
    // of the packed bricks is taken in during the next pass's raster.
    resolver_.startResolve(bricks.words().id(), activeBricks,
                           BrickKeys{bricks.slotBricks().id(), true, item.min / 8, item.bricks()}, fragments);
    pendingTarget_ = &target;
}

void BrickReadback::takeInPassBefore() {
    if (!resolver_.resolvePending()) return;
    resolver_.finishResolve(*pendingTarget_);
    pendingTarget_ = nullptr;
}

std::uint64_t BrickReadback::readRaw(const WorkItem& item, const BrickPass& bricks, GLuint activeBricks) {
    const auto readStart = std::chrono::steady_clock::now();
    const glm::ivec3 itemBricks = item.bricks();
    const std::size_t perBrick = std::size_t(wordsPerVoxel(reduce_, albedo_)) * kBrickVoxels;
    std::vector<std::uint32_t> slotBrick(activeBricks);
    std::memcpy(slotBrick.data(), small_.read(bricks.slotBricks().id(), std::uint64_t(activeBricks) * 4, gpuBytes_),
                std::size_t(activeBricks) * 4);
    const auto* words = static_cast<const std::uint32_t*>(
        raw_.read(bricks.words().id(), std::uint64_t(activeBricks) * perBrick * 4, gpuBytes_));
    std::uint64_t summed = 0;
    for (GLuint slot = 0; slot < activeBricks; ++slot) {
        const std::uint32_t b = slotBrick[slot];
        const glm::ivec3 local(b % itemBricks.x, (b / itemBricks.x) % itemBricks.y, b / (itemBricks.x * itemBricks.y));
        const std::uint64_t key = brickKey(item.min / 8 + local);
        const std::uint32_t* src = words + slot * perBrick;
        auto [it, inserted] = slotOfKey_.try_emplace(key, accumulators_.size());
        if (inserted) {
            accumulators_.push_back({key, std::vector<std::uint32_t>(src, src + perBrick)});
        } else {
            combineAccumulators(reduce_, accumulators_[it->second].words.data(), src, albedo_);
            ++summed;
        }
    }
    rawReadSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - readStart).count();
    return summed;
}

std::vector<BrickAccumulator> BrickReadback::takeAccumulators() {
    std::sort(accumulators_.begin(), accumulators_.end(),
              [](const BrickAccumulator& a, const BrickAccumulator& b) { return a.key < b.key; });
    std::vector<BrickAccumulator> out = std::move(accumulators_);
    accumulators_.clear();
    slotOfKey_.clear();
    return out;
}

void BrickReadback::resolveAccumulators(PackedBricks& out) {
    resolver_.resolve(accumulators_, out);
    accumulators_.clear();
    slotOfKey_.clear();
}

} // namespace yv

#include "core/kept_bricks.h"

#include <utility>

namespace yv {

void KeptBricks::add(const PackedBricks& region) {
    // Copied outside the lock: the copy runs on every core, other regions' too.
    PackedBricks copy;
    copy.append(region.headers.data(), region.headers.size(), region.voxels.data(), region.voxels.size(),
                region.albedo.empty() ? nullptr : region.albedo.data());
    const std::lock_guard lock(mutex_);
    packed_.push_back(std::move(copy));
}

void KeptBricks::add(const std::vector<VoxelBrick>& region) {
    std::vector<VoxelBrick> copy = region;
    const std::lock_guard lock(mutex_);
    resolved_.push_back(std::move(copy));
}

std::size_t KeptBricks::brickCount() const {
    const std::lock_guard lock(mutex_);
    std::size_t n = 0;
    for (const PackedBricks& r : packed_) n += r.headers.size();
    for (const std::vector<VoxelBrick>& r : resolved_) n += r.size();
    return n;
}

std::size_t KeptBricks::bytes() const {
    const std::lock_guard lock(mutex_);
    std::size_t n = 0;
    for (const PackedBricks& r : packed_) n += r.bytes();
    for (const std::vector<VoxelBrick>& r : resolved_) n += r.capacity() * sizeof(VoxelBrick);
    return n;
}

} // namespace yv

#include "inspect/volume_source.h"

#include "core/error.h"
#include "inspect/inspect_vdb.h"

#include <algorithm>
#include <atomic>
#include <filesystem>

namespace yv {

VolumeSource::VolumeSource() {
    static std::atomic<std::uint64_t> next{1};
    id_ = next++;
}

const std::vector<glm::ivec3>& VolumeSource::occupiedLevelBricks(int level) const {
    YV_CHECK(level == 0);
    return occupied_;
}

VoxelBox VolumeSource::bounds() const {
    const std::vector<glm::ivec3>& occupied = occupiedBricks();
    if (occupied.empty()) return {};
    glm::ivec3 lo = occupied.front(), hi = occupied.front();
    for (const glm::ivec3& c : occupied) lo = glm::min(lo, c), hi = glm::max(hi, c);
    return {lo * kBrickSize, (hi + 1) * kBrickSize};
}

namespace {

class MemorySource final : public VolumeSource {
  public:
    MemorySource(const BrickVolume& volume, std::vector<VoxelBox> regions)
        : bricks_(volume.bricks), regions_(std::move(regions)) {
        for (const VoxelBrick& b : bricks_)
            if (b.activeCount()) occupied_.push_back(brickCoord(b.key));
        hasOrientation_ = true;
    }
    VoxelBox regionBounds(std::uint64_t id) const override {
        if (id >= regions_.size()) throw Error("no region " + std::to_string(id) + " in this volume");
        return regions_[id];
    }
    void visitBricks(int level, glm::ivec3 lo, glm::ivec3 hi, const Visit& visit, bool) const override {
        YV_CHECK(level == 0);
        std::array<float, kBrickVoxels> density;
        for (const VoxelBrick& b : bricks_) {
            const glm::ivec3 c = brickCoord(b.key);
            if (!b.activeCount() || glm::any(glm::lessThan(c, lo)) || glm::any(glm::greaterThanEqual(c, hi))) continue;
            for (int v = 0; v < kBrickVoxels; ++v) density[std::size_t(v)] = b.isActive(v) ? b.density[std::size_t(v)] : 0.0f;
            visit(SourceBrick{c, density.data(), b.orientation.data()});
        }
    }

  private:
    std::vector<VoxelBrick> bricks_;
    std::vector<VoxelBox> regions_;
};

} // namespace

std::unique_ptr<VolumeSource> memorySource(const BrickVolume& volume, std::vector<VoxelBox> regions) {
    return std::make_unique<MemorySource>(volume, std::move(regions));
}

VoxelBox recordedRegionBox(const std::vector<RecordedRegion>& regions, std::uint64_t id, const std::string& path) {
    if (regions.empty()) throw Error(vdbHasNoRegions(path));
    for (const RecordedRegion& r : regions)
        if (r.id == id) return VoxelBox{r.min, r.max};
    throw Error(path + ": has no region " + std::to_string(id) + " (it records " + std::to_string(regions.size()) +
                " zoom regions)");
}

std::unique_ptr<VolumeSource> openVolumeSource(const std::string& path) {
    if (std::filesystem::is_directory(path)) return openStoreSource(path);
    return openVdbSource(path);
}

} // namespace yv

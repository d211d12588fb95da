// A work directory as a render's source: which bricks each region holds comes
// from the region files' key indexes (header and index only, checksummed);
// voxels are decoded one region at a time, only for regions holding a wanted brick.
#include "inspect/volume_source.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "store/brick_store.h"
#include "store/region_file.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>

namespace yv {
namespace {

/// Reads `n` bytes at `offset` of `path`, all of them or throws.
void readAt(int fd, const std::string& path, std::uint8_t* out, std::size_t n, std::uint64_t offset) {
    while (n) {
        const ssize_t got = ::pread(fd, out, n, off_t(offset));
        if (got < 0 && errno == EINTR) continue;
        if (got <= 0) throw Error(path + ": cannot read at byte " + std::to_string(offset) + ": " +
                                  (got < 0 ? errnoText(errno) : std::string("file ends early")));
        out += got, n -= std::size_t(got), offset += std::uint64_t(got);
    }
}

/// The brick keys of one region file, after the header and table checks.
std::vector<std::uint64_t> regionKeys(const std::string& path) {
    Fd fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
    if (fd.get() < 0) throw Error(path + ": cannot open: " + errnoText(errno));
    const off_t size = ::lseek(fd.get(), 0, SEEK_END);
    if (size < 0) throw Error(path + ": cannot read its size: " + errnoText(errno));
    std::array<std::uint8_t, kRegionHeaderSize> head{};
    readAt(fd.get(), path, head.data(), std::min<std::size_t>(head.size(), std::size_t(size)), 0);
    const RegionHeader h = parseRegionHeader(head.data(), std::uint64_t(size), path);
    std::vector<std::uint8_t> table(h.dataOffset() - h.indexOffset());
    readAt(fd.get(), path, table.data(), table.size(), h.indexOffset());
    if (xxh64(table.data(), table.size()) != h.tableChecksum) throw Error(path + ": key index checksum mismatch");
    std::vector<std::uint64_t> keys(h.brickCount);
    for (std::size_t i = 0; i < keys.size(); ++i) {
        std::uint64_t k = 0;
        for (int b = 7; b >= 0; --b) k = (k << 8) | table[8 * i + std::size_t(b)];
        keys[i] = k;
    }
    return keys;
}

class StoreSource final : public VolumeSource {
  public:
    explicit StoreSource(const std::string& dir) : store_(dir) {
        for (const RegionInfo& r : store_.listRegions()) {
            Region region{r, {}};
            for (std::uint64_t k : regionKeys(store_.regionPath(r.id))) region.bricks.push_back(brickCoord(k));
            occupied_.insert(occupied_.end(), region.bricks.begin(), region.bricks.end());
            regions_.push_back(std::move(region));
        }
        std::sort(occupied_.begin(), occupied_.end(), [](glm::ivec3 a, glm::ivec3 b) { return brickKey(a) < brickKey(b); });
        hasOrientation_ = true;
    }
    VoxelBox regionBounds(std::uint64_t id) const override {
        for (const Region& r : regions_)
            if (r.info.id == id) return {r.info.min, r.info.max};
        throw Error(store_.dir() + ": has no region " + std::to_string(id));
    }
    void visitBricks(int level, glm::ivec3 lo, glm::ivec3 hi, const Visit& visit, bool concurrent) const override {
        YV_CHECK(level == 0);
        const auto inside = [&](glm::ivec3 c) {
            return !glm::any(glm::lessThan(c, lo)) && !glm::any(glm::greaterThanEqual(c, hi));
        };
        for (const Region& r : regions_) {
            if (std::none_of(r.bricks.begin(), r.bricks.end(), inside)) continue;
            const std::vector<VoxelBrick> bricks = store_.readRegion(r.info.id);
            const auto visitOne = [&](const VoxelBrick& b, std::array<float, kBrickVoxels>& density) {
                const glm::ivec3 c = brickCoord(b.key);
                if (!inside(c)) return;
                for (int v = 0; v < kBrickVoxels; ++v)
                    density[std::size_t(v)] = b.isActive(v) ? b.density[std::size_t(v)] : 0.0f;
                visit(SourceBrick{c, density.data(), b.orientation.data(), b.activeMask.data()});
            };
            if (concurrent) {
                tbb::parallel_for(tbb::blocked_range<std::size_t>(0, bricks.size(), 64), [&](const auto& range) {
                    std::array<float, kBrickVoxels> density;
                    for (std::size_t i = range.begin(); i != range.end(); ++i) visitOne(bricks[i], density);
                });
            } else {
                std::array<float, kBrickVoxels> density;
                for (const VoxelBrick& b : bricks) visitOne(b, density);
            }
        }
    }

  private:
    struct Region {
        RegionInfo info;
        std::vector<glm::ivec3> bricks;
    };
    BrickStore store_;
    std::vector<Region> regions_;
};

} // namespace

std::unique_ptr<VolumeSource> openStoreSource(const std::string& dir) { return std::make_unique<StoreSource>(dir); }

} // namespace yv

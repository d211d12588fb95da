// A work directory as a render's source: which bricks each region holds comes
// from the region files' key indexes (header and index only, checksummed);
// voxels are read chunk by chunk, on every core, only from regions holding a
// wanted brick, and never a whole region at once.
#include "inspect/volume_source.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "store/brick_store.h"
#include "store/region_file.h"

#include <tbb/parallel_for.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <mutex>

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
        // Chunks are read and decoded on every core even when the visitor
        // takes one brick at a time: then only the calls are serialised.
        std::mutex oneAtATime;
        const auto visitChunk = [&](const RawBricks& bricks) {
            std::array<float, kBrickVoxels> density;
            for (std::size_t i = 0; i < bricks.count; ++i) {
                const glm::ivec3 c = brickCoord(bricks.keys[i]);
                if (!inside(c)) continue;
                const std::uint64_t* mask = bricks.activeMask(i);
                std::array<std::uint64_t, kBrickVoxels / 64> active;
                std::copy(mask, mask + active.size(), active.begin());
                const float* values = bricks.density(i);
                for (int v = 0; v < kBrickVoxels; ++v)
                    density[std::size_t(v)] = (active[std::size_t(v >> 6)] >> (v & 63)) & 1 ? values[v] : 0.0f;
                const SourceBrick brick{c, density.data(), bricks.orientation(i), active.data()};
                if (concurrent) {
                    visit(brick);
                } else {
                    const std::lock_guard lock(oneAtATime);
                    visit(brick);
                }
            }
        };
        std::vector<const Region*> wanted;
        for (const Region& r : regions_)
            if (std::any_of(r.bricks.begin(), r.bricks.end(), inside)) wanted.push_back(&r);
        tbb::parallel_for(std::size_t(0), wanted.size(),
                          [&](std::size_t i) { store_.forEachChunk(wanted[i]->info.id, visitChunk); });
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

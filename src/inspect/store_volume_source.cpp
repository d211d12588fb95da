// A work directory as a render's source: which bricks each region holds comes
// from the region files' key indexes (header and index only, checksummed);
// voxels are read chunk by chunk, on every core, only from regions holding a
// wanted brick, and never a whole region at once.
#include "inspect/volume_source.h"

#include "core/error.h"
#include "store/brick_store.h"
#include "store/region_file.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>

namespace yv {
namespace {

class StoreSource final : public VolumeSource {
  public:
    explicit StoreSource(const std::string& dir) : store_(dir) {
        for (const RegionInfo& r : store_.listRegions()) {
            Region region{r, {}};
            const BrickStore::ChunkReader reader(store_, r.id); // header and key index only
            for (std::uint64_t k : reader.keys()) region.bricks.push_back(brickCoord(k));
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
        std::array<float, kBrickVoxels> serialDensity;
        const auto visitChunk = [&](const RawBricks& bricks, std::array<float, kBrickVoxels>& density) {
            for (std::size_t i = 0; i < bricks.count; ++i) {
                const glm::ivec3 c = brickCoord(bricks.keys[i]);
                if (!inside(c)) continue;
                const std::uint64_t* active = bricks.activeMask(i);
                const float* values = bricks.density(i);
                for (int v = 0; v < kBrickVoxels; ++v)
                    density[std::size_t(v)] = (active[v >> 6] >> (v & 63)) & 1 ? values[v] : 0.0f;
                visit(SourceBrick{c, density.data(), bricks.orientation(i), active});
            }
        };
        std::vector<const Region*> wanted;
        for (const Region& r : regions_)
            if (std::any_of(r.bricks.begin(), r.bricks.end(), inside)) wanted.push_back(&r);
        if (concurrent) {
            tbb::parallel_for(std::size_t(0), wanted.size(), [&](std::size_t i) {
                store_.forEachChunk(wanted[i]->info.id, [&](const RawBricks& bricks) {
                    std::array<float, kBrickVoxels> local;
                    visitChunk(bricks, local);
                });
            });
            return;
        }
        // One visit at a time, on this thread (a visitor may draw: GL calls
        // belong to the thread whose context is current); the chunks are
        // still read and decoded on every core, a group at a time.
        const std::size_t group = std::size_t(std::clamp(tbb::this_task_arena::max_concurrency(), 1, 16));
        std::vector<std::vector<std::uint8_t>> stored(group), raw(group);
        std::vector<RawBricks> decoded(group);
        std::vector<std::string> errors(group);
        for (const Region* r : wanted) {
            const BrickStore::ChunkReader reader(store_, r->info.id);
            std::uint64_t active = 0;
            for (std::size_t first = 0; first < reader.chunkCount(); first += group) {
                const std::size_t count = std::min(group, reader.chunkCount() - first);
                tbb::parallel_for(std::size_t(0), count, [&](std::size_t k) {
                    errors[k].clear();
                    try {
                        decoded[k] = reader.read(first + k, stored[k], raw[k]);
                    } catch (const Error& e) {
                        errors[k] = e.what();
                    }
                });
                for (std::size_t k = 0; k < count; ++k) {
                    if (!errors[k].empty()) throw Error(errors[k]);
                    active += countActive(decoded[k]);
                    visitChunk(decoded[k], serialDensity);
                }
            }
            reader.checkActiveVoxels(active);
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

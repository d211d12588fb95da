// A run's bricks as it kept them in memory (core/kept_bricks.h): packed
// regions are unpacked a brick at a time as a render asks for them, so the
// source holds no more than the run kept.
#include "inspect/volume_source.h"

#include "core/error.h"
#include "core/kept_bricks.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <utility>

namespace yv {
namespace {

class KeptSource final : public VolumeSource {
  public:
    explicit KeptSource(std::shared_ptr<const KeptBricks> kept) : kept_(std::move(kept)) {
        const std::vector<PackedBricks>& packed = kept_->packedRegions();
        const std::vector<std::vector<VoxelBrick>>& resolved = kept_->resolvedRegions();
        for (std::size_t r = 0; r < packed.size(); ++r)
            for (std::size_t i = 0; i < packed[r].headers.size(); ++i)
                entries_.push_back({packed[r].headers[i].brickKey(), Part::Packed, std::uint32_t(r), std::uint32_t(i)});
        for (std::size_t r = 0; r < resolved.size(); ++r)
            for (std::size_t i = 0; i < resolved[r].size(); ++i)
                if (resolved[r][i].activeCount())
                    entries_.push_back({resolved[r][i].key, Part::Resolved, std::uint32_t(r), std::uint32_t(i)});
        std::sort(entries_.begin(), entries_.end(), [](const Entry& a, const Entry& b) { return a.key < b.key; });
        occupied_.reserve(entries_.size());
        for (std::size_t i = 0; i < entries_.size(); ++i) {
            if (i > 0 && entries_[i].key == entries_[i - 1].key)
                throw Error("the view's bricks hold brick " + std::to_string(entries_[i].key) +
                            " twice (regions must not share bricks)");
            occupied_.push_back(brickCoord(entries_[i].key));
        }
        hasOrientation_ = true;
    }

    VoxelBox regionBounds(std::uint64_t id) const override {
        throw Error("no region " + std::to_string(id) + ": bricks kept in memory record no regions");
    }

  protected:
    void visitBricks(int level, glm::ivec3 lo, glm::ivec3 hi, const Visit& visit, bool concurrent) const override {
        YV_CHECK(level == 0);
        std::vector<std::size_t> wanted;
        for (std::size_t i = 0; i < entries_.size(); ++i) {
            const glm::ivec3 c = occupied_[i];
            if (glm::all(glm::greaterThanEqual(c, lo)) && glm::all(glm::lessThan(c, hi))) wanted.push_back(i);
        }
        // A brick unpacked (or copied with its inactive voxels zeroed) into a buffer of its thread's own.
        tbb::enumerable_thread_specific<VoxelBrick> buffers;
        const auto one = [&](std::size_t i) {
            const Entry& e = entries_[i];
            VoxelBrick& b = buffers.local();
            if (e.part == Part::Packed) {
                unpackBrick(kept_->packedRegions()[e.region], e.index, b);
            } else {
                b = kept_->resolvedRegions()[e.region][e.index];
                for (int v = 0; v < kBrickVoxels; ++v)
                    if (!b.isActive(v)) b.density[std::size_t(v)] = 0.0f;
            }
            visit(SourceBrick{occupied_[i], b.density.data(), b.orientation.data(), b.activeMask.data()});
        };
        if (concurrent) {
            tbb::parallel_for(std::size_t(0), wanted.size(), [&](std::size_t k) { one(wanted[k]); });
        } else {
            for (std::size_t i : wanted) one(i);
        }
    }

  private:
    enum class Part : std::uint8_t { Packed, Resolved };
    struct Entry {
        std::uint64_t key;
        Part part;
        std::uint32_t region, index;
    };
    std::shared_ptr<const KeptBricks> kept_;
    std::vector<Entry> entries_; ///< sorted by key, as occupied_
};

} // namespace

std::unique_ptr<VolumeSource> keptBricksSource(std::shared_ptr<const KeptBricks> bricks) {
    return std::make_unique<KeptSource>(std::move(bricks));
}

} // namespace yv

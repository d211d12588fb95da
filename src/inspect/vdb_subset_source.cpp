// A yarnvox .vdb as a render's source, read by yarnvox's own reader
// (vdb/vdb_index.h): opening reads the headers; a level's topology is read
// the first time that level is asked for; leaf values are read in ranges of
// consecutive leaves, decoded in parallel and dropped once visited, so
// memory holds the leaf table and a few ranges, never the volume.
#include "inspect/volume_source.h"

#include "core/error.h"
#include "core/run_metadata.h"
#include "inspect/inspect_vdb.h"
#include "vdb/leaf_records.h"
#include "vdb/vdb_index.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <mutex>

namespace yv {
namespace {

/// OpenVDB's grid metadata item with the active voxel count.
constexpr const char* kVoxelCountItem = "file_voxel_count";
/// Leaves decoded together: one read per grid.
constexpr std::size_t kPieceLeaves = 256;
/// Pieces decoded side by side before an in-order visit (about 64 MB).
constexpr std::size_t kPiecesPerChunk = 32;

template <typename T> std::optional<T> podOf(const VdbGridInfo& g, const std::string& name, const std::string& type) {
    const StoredMetadata* m = g.find(name);
    if (!m || m->type != type || m->value.size() != sizeof(T)) return std::nullopt;
    T value;
    std::memcpy(&value, m->value.data(), sizeof value);
    return value;
}

struct Piece {
    std::size_t first, last; ///< leaves [first, last) of the level's table
};

class VdbSubsetSource final : public VolumeSource {
  public:
    explicit VdbSubsetSource(std::unique_ptr<VdbIndex> index) : index_(std::move(index)) {
        const std::string& path = index_->path();
        const VdbGridInfo* density = index_->grid("density");
        if (!density || density->vector) throw Error(path + ": has no float grid named 'density'");
        const VdbGridInfo* orientation = index_->grid("orientation");
        hasOrientation_ = orientation && orientation->vector;
        levels_[0].density = density;
        levels_[0].orientation = hasOrientation_ ? orientation : nullptr;
        for (const VdbGridInfo& g : index_->grids()) {
            if (g.lodLevel <= 0 || g.vector || g.name != "density_lod" + std::to_string(g.lodLevel)) continue;
            const VdbGridInfo* axes = index_->grid("orientation_lod" + std::to_string(g.lodLevel));
            if (hasOrientation_ && !(axes && axes->vector)) continue;
            levels_[g.lodLevel].density = &g;
            levels_[g.lodLevel].orientation = hasOrientation_ ? axes : nullptr;
        }
        storedLevels_.clear();
        for (const auto& [level, grids] : levels_) storedLevels_.push_back(level);
        if (const StoredMetadata* regions = density->find(kRegionsMetadataName); regions && regions->type == "string")
            regions_ = decodeRegions(std::string(regions->value.begin(), regions->value.end()),
                                     path + ": density grid metadata " + kRegionsMetadataName);
    }

    const std::vector<glm::ivec3>& occupiedLevelBricks(int level) const override { return loaded(level).sorted; }

    std::uint64_t occupiedBricksAtLeast(int level) const override {
        const Level& l = levelOf(level);
        {
            std::lock_guard lock(mutex_);
            if (l.loaded) return l.sorted.size();
        }
        const auto voxels = podOf<std::int64_t>(*l.density, kVoxelCountItem, "int64");
        return voxels ? std::uint64_t(*voxels + 511) / 512 : occupiedLevelBricks(level).size();
    }

    VoxelBox bounds() const override {
        const VdbGridInfo& d = *levelOf(0).density;
        const auto lo = podOf<glm::ivec3>(d, "file_bbox_min", "vec3i");
        const auto hi = podOf<glm::ivec3>(d, "file_bbox_max", "vec3i");
        const auto voxels = podOf<std::int64_t>(d, kVoxelCountItem, "int64");
        if (!lo || !hi || !voxels) return VolumeSource::bounds();
        if (*voxels == 0) return {};
        return {(*lo >> 3) * kBrickSize, ((*hi >> 3) + 1) * kBrickSize};
    }

    VoxelBox regionBounds(std::uint64_t id) const override { return recordedRegionBox(regions_, id, index_->path()); }

  protected:
    void visitBricks(int level, glm::ivec3 lo, glm::ivec3 hi, const Visit& visit, bool concurrent) const override {
        const Level& l = loaded(level);
        const std::vector<Piece> pieces = piecesInside(l.table, lo, hi);
        if (concurrent) {
            // Buffers kept per thread: a fresh 2 MB of them per piece cost more in page faults than the decoding.
            // Each leaf is visited as soon as it is decoded, while its 8 KB are still in the core's cache.
            tbb::enumerable_thread_specific<Decoded> buffers;
            tbb::parallel_for(std::size_t(0), pieces.size(), [&](std::size_t p) {
                Decoded& d = buffers.local();
                read(l, pieces[p], d);
                d.density.resize(kBrickVoxels);
                d.axes.resize(l.orientation ? 3 * kBrickVoxels : 0);
                d.active.resize(8);
                for (std::size_t leaf = pieces[p].first; leaf < pieces[p].last; ++leaf) {
                    decodeLeaf(l, pieces[p], leaf, d, d.density.data(), d.axes.data(), d.active.data());
                    visit(SourceBrick{l.table.bricks[leaf], d.density.data(),
                                      l.orientation ? reinterpret_cast<const glm::vec3*>(d.axes.data()) : nullptr,
                                      d.active.data()});
                }
            });
            return;
        }
        std::vector<Decoded> decoded(kPiecesPerChunk);
        for (std::size_t first = 0; first < pieces.size(); first += kPiecesPerChunk) {
            const std::size_t count = std::min(kPiecesPerChunk, pieces.size() - first);
            tbb::parallel_for(std::size_t(0), count, [&](std::size_t p) { decode(l, pieces[first + p], decoded[p]); });
            for (std::size_t p = 0; p < count; ++p) visitDecoded(l, pieces[first + p], decoded[p], visit);
        }
    }

  private:
    struct Level {
        const VdbGridInfo* density = nullptr;
        const VdbGridInfo* orientation = nullptr;
        bool loaded = false;
        VdbLeafTable table;                    ///< the density grid's leaves
        std::vector<std::uint64_t> axisRecords; ///< the orientation grid's records, same leaves
        std::vector<glm::ivec3> sorted;        ///< table.bricks in brickKey order
    };
    struct Decoded {
        std::vector<std::uint8_t> densityBytes, axisBytes;
        std::vector<float> density, axes;
        std::vector<std::uint64_t> active; ///< 8 words a leaf
    };

    const Level& levelOf(int level) const {
        const auto it = levels_.find(level);
        YV_CHECK(it != levels_.end());
        return it->second;
    }

    const Level& loaded(int level) const {
        std::lock_guard lock(mutex_);
        auto it = levels_.find(level);
        YV_CHECK(it != levels_.end());
        Level& l = it->second;
        if (l.loaded) return l;
        l.table = index_->leaves(*l.density);
        if (l.orientation) {
            VdbLeafTable axes = index_->leaves(*l.orientation);
            if (axes.bricks != l.table.bricks)
                throw Error(index_->path() + ": grids '" + l.density->name + "' and '" + l.orientation->name +
                            "' have different leaves (damaged, or not one volume)");
            l.axisRecords = std::move(axes.records);
        }
        l.sorted = l.table.bricks;
        tbb::parallel_sort(l.sorted.begin(), l.sorted.end(),
                           [](glm::ivec3 a, glm::ivec3 b) { return brickKey(a) < brickKey(b); });
        l.loaded = true;
        return l;
    }

    static std::vector<Piece> piecesInside(const VdbLeafTable& table, glm::ivec3 lo, glm::ivec3 hi) {
        std::vector<Piece> pieces;
        for (std::size_t i = 0; i < table.bricks.size();) {
            const glm::ivec3 c = table.bricks[i];
            if (glm::any(glm::lessThan(c, lo)) || glm::any(glm::greaterThanEqual(c, hi))) {
                ++i;
                continue;
            }
            if (!pieces.empty() && pieces.back().last == i && i - pieces.back().first < kPieceLeaves)
                ++pieces.back().last;
            else
                pieces.push_back({i, i + 1});
            ++i;
        }
        return pieces;
    }

    /// Reads the piece's records of each grid: one read per grid.
    void read(const Level& l, const Piece& piece, Decoded& d) const {
        readLeafRecords(*index_, *l.density, l.table, piece.first, piece.last, d.densityBytes);
        if (l.orientation) {
            const std::uint64_t axisBase = l.axisRecords[piece.first];
            d.axisBytes.resize(std::size_t(l.axisRecords[piece.last] - axisBase));
            index_->file().read(axisBase, d.axisBytes, "grid '" + l.orientation->name + "' leaves");
        }
    }

    /// Decodes leaf `leaf` of a piece whose records `read` put in `d`.
    void decodeLeaf(const Level& l, const Piece& piece, std::size_t leaf, const Decoded& d, float* density, float* axes,
                    std::uint64_t* active) const {
        const std::uint64_t base = l.table.records[piece.first];
        const std::span<const std::uint8_t> record(d.densityBytes.data() + (l.table.records[leaf] - base),
                                                   l.table.records[leaf + 1] - l.table.records[leaf]);
        decodeLeafRecord(record, *index_, *l.density, leaf, l.table.bricks[leaf], l.table.records[leaf], density, active);
        if (!l.orientation) return;
        const std::uint64_t axisBase = l.axisRecords[piece.first];
        const std::span<const std::uint8_t> axisRecord(d.axisBytes.data() + (l.axisRecords[leaf] - axisBase),
                                                       l.axisRecords[leaf + 1] - l.axisRecords[leaf]);
        decodeLeafRecord(axisRecord, *index_, *l.orientation, leaf, l.table.bricks[leaf], l.axisRecords[leaf], axes);
    }

    /// Reads and decodes a whole piece into `d`'s arrays.
    void decode(const Level& l, const Piece& piece, Decoded& d) const {
        const std::size_t n = piece.last - piece.first;
        read(l, piece, d);
        d.density.resize(n * kBrickVoxels);
        d.active.resize(n * 8);
        d.axes.resize(l.orientation ? n * kBrickVoxels * 3 : 0);
        for (std::size_t i = 0; i < n; ++i)
            decodeLeaf(l, piece, piece.first + i, d, d.density.data() + i * kBrickVoxels,
                       l.orientation ? d.axes.data() + i * kBrickVoxels * 3 : nullptr, d.active.data() + i * 8);
    }

    static void visitDecoded(const Level& l, const Piece& piece, const Decoded& d, const Visit& visit) {
        for (std::size_t i = 0; i < piece.last - piece.first; ++i)
            visit(SourceBrick{l.table.bricks[piece.first + i], d.density.data() + i * kBrickVoxels,
                              l.orientation ? reinterpret_cast<const glm::vec3*>(d.axes.data()) + i * kBrickVoxels : nullptr,
                              d.active.data() + i * 8});
    }

    std::unique_ptr<VdbIndex> index_;
    mutable std::mutex mutex_;
    mutable std::map<int, Level> levels_;
    std::vector<RecordedRegion> regions_;
};

} // namespace

std::unique_ptr<VolumeSource> openVdbSource(const std::string& path) {
    auto index = std::make_unique<VdbIndex>(path);
    if (!index->inSubset()) return openVdbSourceThroughOpenVdb(path);
    return std::make_unique<VdbSubsetSource>(std::move(index));
}

} // namespace yv

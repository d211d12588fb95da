// A .vdb as a render's source, through OpenVDB with delayed loading (files
// outside the subset yarnvox reads itself, vdb_subset_source.cpp): opening
// reads the topology only; a leaf's voxels are read from the file when a
// render asks for that leaf.
#include "inspect/volume_source.h"

#include "core/error.h"
#include "inspect/inspect_vdb.h"

#include <openvdb/openvdb.h>

#include <algorithm>
#include <array>

namespace yv {
namespace {

glm::ivec3 brickOf(const openvdb::Coord& origin) { return {origin.x() >> 3, origin.y() >> 3, origin.z() >> 3}; }

struct Grids {
    openvdb::FloatGrid::Ptr density;
    openvdb::Vec3SGrid::Ptr orientation;
};

/// The file's density and orientation grids with delayed loading: topology
/// now, a leaf's values when first touched.
Grids openGrids(const std::string& path) {
    openvdb::initialize();
    openvdb::io::File file(path);
    Grids g;
    try {
        file.open(/*delayLoad=*/true);
        if (file.hasGrid("density")) g.density = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("density"));
        if (file.hasGrid("orientation"))
            g.orientation = openvdb::gridPtrCast<openvdb::Vec3SGrid>(file.readGrid("orientation"));
    } catch (const openvdb::Exception& e) {
        throw Error(path + ": not an OpenVDB file OpenVDB can read (" + e.what() + ")");
    }
    file.close();
    if (!g.density) throw Error(path + ": has no float grid named 'density'");
    return g;
}

/// Removes the leaf at `origin` from `tree` and frees it: a delayed-load
/// leaf, once touched, would otherwise keep its values for good.
template <typename TreeT> void dropLeaf(TreeT& tree, const openvdb::Coord& origin) {
    using LeafT = typename TreeT::LeafNodeType;
    delete tree.template stealNode<LeafT>(origin, typename TreeT::ValueType(0), false);
}

class VdbSource final : public VolumeSource {
  public:
    explicit VdbSource(const std::string& path) : path_(path) {
        const Grids g = openGrids(path);
        hasOrientation_ = g.orientation != nullptr;
        regions_ = recordedRegionsOf(*g.density, path);
        for (auto leaf = g.density->tree().cbeginLeaf(); leaf; ++leaf)
            if (!leaf->isEmpty()) occupied_.push_back(brickOf(leaf->origin()));
        std::sort(occupied_.begin(), occupied_.end(), [](glm::ivec3 a, glm::ivec3 b) {
            return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z < b.z;
        });
    }
    VoxelBox regionBounds(std::uint64_t id) const override { return recordedRegionBox(regions_, id, path_); }
    /// Each visit reads the grids afresh and frees every leaf once it is
    /// handed on, so memory holds the topology and one leaf, not the leaves
    /// visited so far.
    void visitBricks(int level, glm::ivec3 lo, glm::ivec3 hi, const Visit& visit, bool) const override {
        YV_CHECK(level == 0);
        Grids g = openGrids(path_);
        std::vector<openvdb::Coord> origins;
        for (auto leaf = g.density->tree().cbeginLeaf(); leaf; ++leaf) {
            const glm::ivec3 c = brickOf(leaf->origin());
            if (leaf->isEmpty() || glm::any(glm::lessThan(c, lo)) || glm::any(glm::greaterThanEqual(c, hi))) continue;
            origins.push_back(leaf->origin());
        }
        std::array<float, kBrickVoxels> density;
        std::array<glm::vec3, kBrickVoxels> axes;
        std::array<std::uint64_t, kBrickVoxels / 64> active;
        for (const openvdb::Coord& origin : origins) {
            const auto* leaf = g.density->tree().probeConstLeaf(origin);
            active.fill(0);
            for (int v = 0; v < kBrickVoxels; ++v) {
                const bool on = leaf->isValueOn(openvdb::Index(v));
                density[std::size_t(v)] = on ? leaf->getValue(openvdb::Index(v)) : 0.0f;
                if (on) active[std::size_t(v >> 6)] |= std::uint64_t(1) << (v & 63);
            }
            const auto* o = g.orientation ? g.orientation->tree().probeConstLeaf(origin) : nullptr;
            for (int v = 0; v < kBrickVoxels; ++v) {
                const openvdb::Vec3s a = o ? o->getValue(openvdb::Index(v)) : openvdb::Vec3s(0.0f);
                axes[std::size_t(v)] = {a.x(), a.y(), a.z()};
            }
            visit(SourceBrick{brickOf(origin), density.data(), hasOrientation_ ? axes.data() : nullptr, active.data()});
            dropLeaf(g.density->tree(), origin);
            if (g.orientation) dropLeaf(g.orientation->tree(), origin);
        }
    }

  private:
    std::string path_;
    std::vector<RecordedRegion> regions_; ///< as the density grid's metadata records them
};

} // namespace

std::unique_ptr<VolumeSource> openVdbSourceThroughOpenVdb(const std::string& path) {
    return std::make_unique<VdbSource>(path);
}

} // namespace yv

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

class VdbSource final : public VolumeSource {
  public:
    explicit VdbSource(const std::string& path) : path_(path) {
        openvdb::initialize();
        openvdb::io::File file(path);
        try {
            file.open(/*delayLoad=*/true);
            if (file.hasGrid("density")) density_ = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("density"));
            if (file.hasGrid("orientation"))
                orientation_ = openvdb::gridPtrCast<openvdb::Vec3SGrid>(file.readGrid("orientation"));
        } catch (const openvdb::Exception& e) {
            throw Error(path + ": not an OpenVDB file OpenVDB can read (" + e.what() + ")");
        }
        file.close();
        if (!density_) throw Error(path + ": has no float grid named 'density'");
        hasOrientation_ = orientation_ != nullptr;
        regions_ = recordedRegionsOf(*density_, path);
        for (auto leaf = density_->tree().cbeginLeaf(); leaf; ++leaf)
            if (!leaf->isEmpty()) occupied_.push_back(brickOf(leaf->origin()));
        std::sort(occupied_.begin(), occupied_.end(), [](glm::ivec3 a, glm::ivec3 b) {
            return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z < b.z;
        });
    }
    VoxelBox regionBounds(std::uint64_t id) const override {
        if (regions_.empty()) throw Error(vdbHasNoRegions(path_));
        for (const RecordedRegion& r : regions_)
            if (r.id == id) return VoxelBox{r.min, r.max};
        throw Error(path_ + ": has no region " + std::to_string(id) + " (it records " + std::to_string(regions_.size()) +
                    " zoom regions)");
    }
    void visitBricks(int level, glm::ivec3 lo, glm::ivec3 hi, const Visit& visit, bool) const override {
        YV_CHECK(level == 0);
        std::array<float, kBrickVoxels> density;
        std::array<glm::vec3, kBrickVoxels> axes;
        for (auto leaf = density_->tree().cbeginLeaf(); leaf; ++leaf) {
            const glm::ivec3 c = brickOf(leaf->origin());
            if (leaf->isEmpty() || glm::any(glm::lessThan(c, lo)) || glm::any(glm::greaterThanEqual(c, hi))) continue;
            for (int v = 0; v < kBrickVoxels; ++v)
                density[std::size_t(v)] = leaf->isValueOn(openvdb::Index(v)) ? leaf->getValue(openvdb::Index(v)) : 0.0f;
            const openvdb::Vec3SGrid::TreeType::LeafNodeType* o =
                orientation_ ? orientation_->tree().probeConstLeaf(leaf->origin()) : nullptr;
            for (int v = 0; v < kBrickVoxels; ++v) {
                const openvdb::Vec3s a = o ? o->getValue(openvdb::Index(v)) : openvdb::Vec3s(0.0f);
                axes[std::size_t(v)] = {a.x(), a.y(), a.z()};
            }
            visit(SourceBrick{c, density.data(), hasOrientation_ ? axes.data() : nullptr});
        }
    }

  private:
    std::string path_;
    openvdb::FloatGrid::Ptr density_;
    openvdb::Vec3SGrid::Ptr orientation_;
    std::vector<RecordedRegion> regions_; ///< as the density grid's metadata records them
};

} // namespace

std::unique_ptr<VolumeSource> openVdbSourceThroughOpenVdb(const std::string& path) {
    return std::make_unique<VdbSource>(path);
}

} // namespace yv

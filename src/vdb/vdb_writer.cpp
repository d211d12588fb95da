#include "vdb/vdb_writer.h"

#include "core/error.h"

#include <openvdb/openvdb.h>
#include <tbb/parallel_for.h>

#include <cstdio>
#include <fcntl.h>
#include <unistd.h>
#include <filesystem>

namespace yv {
namespace {

/// Leaves are built in parallel; inserting them into the tree is serial
/// (addLeaf is not thread-safe) but costs one pointer move per leaf.
template <class GridT, class Fill>
typename GridT::Ptr buildGrid(const BrickVolume& volume, typename GridT::ValueType background, Fill&& fill) {
    using LeafT = typename GridT::TreeType::LeafNodeType;
    std::vector<LeafT*> leaves(volume.bricks.size());
    tbb::parallel_for(std::size_t(0), volume.bricks.size(), [&](std::size_t i) {
        const VoxelBrick& b = volume.bricks[i];
        const glm::ivec3 origin = brickCoord(b.key) * 8;
        auto* leaf = new LeafT(openvdb::Coord(origin.x, origin.y, origin.z), background, false);
        for (int v = 0; v < kBrickVoxels; ++v)
            if (b.isActive(v)) leaf->setValueOn(v, fill(b, v));
        leaves[i] = leaf;
    });
    auto grid = GridT::create(background);
    for (LeafT* leaf : leaves) grid->tree().addLeaf(leaf);
    return grid;
}

} // namespace

void writeVdb(const std::string& path, const BrickVolume& volume, const VolumeMetadata& metadata) {
    openvdb::initialize();
    const double h = volume.grid.voxelSize;
    auto transform = openvdb::math::Transform::createLinearTransform(h);
    const glm::dvec3 c = volume.grid.origin + 0.5 * h;
    transform->postTranslate(openvdb::Vec3d(c.x, c.y, c.z));

    auto density = buildGrid<openvdb::FloatGrid>(volume, 0.0f, [](const VoxelBrick& b, int v) { return b.density[v]; });
    density->setName("density");
    density->setGridClass(openvdb::GRID_FOG_VOLUME);
    density->setTransform(transform);

    auto orientation = buildGrid<openvdb::Vec3SGrid>(volume, openvdb::Vec3s(0.0f), [](const VoxelBrick& b, int v) {
        const glm::vec3 o = b.orientation[v];
        return openvdb::Vec3s(o.x, o.y, o.z);
    });
    orientation->setName("orientation");
    orientation->setVectorType(openvdb::VEC_INVARIANT); // an axis: not transformed like a position
    orientation->setTransform(transform);

    openvdb::MetaMap meta;
    meta.insertMeta("yarnvox_version", openvdb::StringMetadata(YV_VERSION));
    meta.insertMeta("input", openvdb::StringMetadata(metadata.input));
    meta.insertMeta("backend", openvdb::StringMetadata(metadata.backend));
    meta.insertMeta("cross_section", openvdb::StringMetadata(metadata.crossSection));
    meta.insertMeta("resolution", openvdb::Int32Metadata(metadata.resolution));
    meta.insertMeta("voxel_size", openvdb::DoubleMetadata(h));
    meta.insertMeta("reduce", openvdb::StringMetadata(toString(volume.reduce)));
    meta.insertMeta("slice_count", openvdb::Int64Metadata(static_cast<std::int64_t>(metadata.sliceCount)));
    meta.insertMeta("yarn_radius", openvdb::DoubleMetadata(metadata.yarnRadius));
    meta.insertMeta("twist", openvdb::DoubleMetadata(metadata.twist));
    meta.insertMeta("supersample", openvdb::Int32Metadata(metadata.supersample));
    meta.insertMeta("grid_dims", openvdb::Vec3IMetadata(openvdb::Vec3i(volume.grid.dims.x, volume.grid.dims.y,
                                                                           volume.grid.dims.z)));

    const std::string tmp = path + ".partial";
    try {
        openvdb::io::File file(tmp);
        file.write({density, orientation}, meta);
        file.close();
    } catch (const openvdb::Exception& e) {
        std::remove(tmp.c_str());
        throw Error(path + ": cannot write OpenVDB file: " + e.what());
    }
    // Data on disk before the name: a crash never leaves a complete-looking file.
    if (int fd = ::open(tmp.c_str(), O_RDONLY); fd >= 0) {
        ::fsync(fd);
        ::close(fd);
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::remove(tmp.c_str());
        throw Error(path + ": cannot rename the finished file into place: " + ec.message());
    }
}

} // namespace yv

#include "vdb/vdb_writer.h"

#include "core/error.h"
#include "core/text.h"

#include <openvdb/openvdb.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <atomic>
#include <chrono>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <fcntl.h>
#include <filesystem>
#include <mutex>
#include <unistd.h>

namespace yv {
namespace {

using DensityLeaf = openvdb::FloatGrid::TreeType::LeafNodeType;
using OrientationLeaf = openvdb::Vec3SGrid::TreeType::LeafNodeType;

void fsyncPath(const std::string& path, int flags) {
    if (int fd = ::open(path.c_str(), flags | O_CLOEXEC); fd >= 0) {
        ::fsync(fd);
        ::close(fd);
    }
}

/// OpenVDB's io::File::write opens its own stream and never looks at it
/// again: a full disk ends in a truncated file and no error. This archive
/// writes the same bytes (Archive::write, seekable, as io::File does) into a
/// stream the caller owns and checks.
class CheckedArchive : public openvdb::io::Archive {
  public:
    void writeTo(std::ostream& os, const openvdb::GridCPtrVec& grids, const openvdb::MetaMap& meta) const {
        openvdb::io::Archive::write(os, grids, /*seekable=*/true, meta);
    }
};

/// Writes the grids to `tmp` and makes them durable; throws yv::Error naming
/// `path` and the system's reason when any write, the close or the fsync fails.
void writeGridsChecked(const std::string& path, const std::string& tmp, const openvdb::GridCPtrVec& grids,
                       const openvdb::MetaMap& meta, std::uint32_t compression) {
    CheckedArchive archive;
    archive.setCompression(compression);
    std::ofstream out(tmp, std::ios::out | std::ios::binary | std::ios::trunc);
    if (!out) throw Error(path + ": cannot create " + tmp + ": " + std::strerror(errno));
    errno = 0;
    archive.writeTo(out, grids, meta);
    out.flush();
    const int writeErrno = errno;
    if (!out.good()) {
        const std::string why = writeErrno ? std::strerror(writeErrno) : "the write failed";
        throw Error(path + ": cannot write the OpenVDB file (" + why + ")");
    }
    out.close();
    if (out.fail()) throw Error(path + ": cannot close the OpenVDB file (" + std::strerror(errno) + ")");
    // Data on disk before the name: a crash never leaves a complete-looking file.
    const int fd = ::open(tmp.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0 || ::fsync(fd) != 0) {
        const std::string why = std::strerror(errno);
        if (fd >= 0) ::close(fd);
        throw Error(path + ": cannot make the OpenVDB file durable (" + why + ")");
    }
    ::close(fd);
}

} // namespace

struct VdbAssembler::Impl {
    struct Entry {
        std::uint64_t key = 0;
        std::uint32_t source = 0;
        std::unique_ptr<DensityLeaf> density;
        std::unique_ptr<OrientationLeaf> orientation;
    };

    VoxelGrid grid;
    Reduce reduce = Reduce::Mean;
    mutable std::mutex mutex;
    std::vector<Entry> entries;
    std::vector<std::string> sources;
    bool written = false;
};

VdbAssembler::VdbAssembler(const VoxelGrid& grid, Reduce reduce) : impl_(std::make_unique<Impl>()) {
    openvdb::initialize();
    impl_->grid = grid;
    impl_->reduce = reduce;
}

VdbAssembler::~VdbAssembler() = default;

void VdbAssembler::add(std::span<const VoxelBrick> bricks, const std::string& source) {
    // Leaves are built in parallel, outside the lock; only the hand-over is serial.
    std::vector<Impl::Entry> local(bricks.size());
    tbb::parallel_for(std::size_t(0), bricks.size(), [&](std::size_t i) {
        const VoxelBrick& b = bricks[i];
        const glm::ivec3 o = brickCoord(b.key) * 8;
        const openvdb::Coord origin(o.x, o.y, o.z);
        auto density = std::make_unique<DensityLeaf>(origin, 0.0f, false);
        auto orientation = std::make_unique<OrientationLeaf>(origin, openvdb::Vec3s(0.0f), false);
        for (int v = 0; v < kBrickVoxels; ++v)
            if (b.isActive(v)) {
                density->setValueOn(v, b.density[v]);
                const glm::vec3 a = b.orientation[v];
                orientation->setValueOn(v, openvdb::Vec3s(a.x, a.y, a.z));
            }
        local[i] = {b.key, 0, std::move(density), std::move(orientation)};
    });
    std::lock_guard lock(impl_->mutex);
    const auto tag = static_cast<std::uint32_t>(impl_->sources.size());
    impl_->sources.push_back(source);
    impl_->entries.reserve(impl_->entries.size() + local.size());
    for (Impl::Entry& e : local) {
        e.source = tag;
        impl_->entries.push_back(std::move(e));
    }
}

std::size_t VdbAssembler::brickCount() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->entries.size();
}

const char* toString(VdbCompression c) {
    switch (c) {
    case VdbCompression::Blosc: return "blosc";
    case VdbCompression::Zip: return "zip";
    case VdbCompression::ActiveMask: return "mask";
    case VdbCompression::None: return "none";
    }
    return "?";
}

VdbCompression parseVdbCompression(const std::string& name) {
    for (VdbCompression c : {VdbCompression::Blosc, VdbCompression::Zip, VdbCompression::ActiveMask, VdbCompression::None})
        if (name == toString(c)) return c;
    throw Error("unknown .vdb compression '" + name + "': expected blosc, zip, mask or none");
}

void VdbAssembler::write(const std::string& path, const VolumeMetadata& metadata, const VdbWriteOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    std::lock_guard lock(impl_->mutex);
    YV_CHECK(!impl_->written);
    impl_->written = true;
    auto& entries = impl_->entries;
    tbb::parallel_sort(entries.begin(), entries.end(),
                       [](const Impl::Entry& a, const Impl::Entry& b) { return a.key < b.key; });
    for (std::size_t i = 1; i < entries.size(); ++i)
        if (entries[i].key == entries[i - 1].key) {
            const std::string& a = impl_->sources[entries[i - 1].source];
            const std::string& b = impl_->sources[entries[i].source];
            const std::string from = a.empty() && b.empty() ? "" : " (from " + a + " and " + b + ")";
            throw Error(path + ": brick at voxel " + coordText(brickCoord(entries[i].key) * 8) + " given twice" +
                        from + ": cannot build one volume");
        }

    const VoxelGrid& grid = impl_->grid;
    const double h = grid.voxelSize;
    auto transform = openvdb::math::Transform::createLinearTransform(h);
    const glm::dvec3 c = grid.origin + 0.5 * h;
    transform->postTranslate(openvdb::Vec3d(c.x, c.y, c.z));

    // addLeaf is not thread-safe, but costs one pointer move per leaf.
    auto density = openvdb::FloatGrid::create(0.0f);
    auto orientation = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    for (Impl::Entry& e : entries) {
        density->tree().addLeaf(e.density.release());
        orientation->tree().addLeaf(e.orientation.release());
    }
    std::vector<Impl::Entry>().swap(entries);
    density->setName("density");
    density->setGridClass(openvdb::GRID_FOG_VOLUME);
    density->setTransform(transform);
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
    meta.insertMeta("reduce", openvdb::StringMetadata(toString(impl_->reduce)));
    meta.insertMeta("slice_count", openvdb::Int64Metadata(static_cast<std::int64_t>(metadata.sliceCount)));
    meta.insertMeta("yarn_radius", openvdb::DoubleMetadata(metadata.yarnRadius));
    meta.insertMeta("yarn_radius_source", openvdb::StringMetadata(metadata.yarnRadiusSource));
    meta.insertMeta("twist", openvdb::DoubleMetadata(metadata.twist));
    meta.insertMeta("supersample", openvdb::Int32Metadata(metadata.supersample));
    meta.insertMeta("overlap", openvdb::StringMetadata(metadata.overlap));
    meta.insertMeta("slice_spacing", openvdb::DoubleMetadata(metadata.sliceSpacing));
    meta.insertMeta("grid_dims", openvdb::Vec3IMetadata(openvdb::Vec3i(grid.dims.x, grid.dims.y, grid.dims.z)));

    const auto written = std::chrono::steady_clock::now();
    // A name of this process's own: two runs writing the same output never
    // share a temporary file.
    static std::atomic<unsigned> counter{0};
    const std::string tmp = path + ".partial-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
    std::uint32_t compression = openvdb::io::COMPRESS_NONE;
    switch (options.compression) {
    case VdbCompression::Blosc: compression = openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK; break;
    case VdbCompression::Zip: compression = openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK; break;
    case VdbCompression::ActiveMask: compression = openvdb::io::COMPRESS_ACTIVE_MASK; break;
    case VdbCompression::None: break;
    }
    try {
        writeGridsChecked(path, tmp, {density, orientation}, meta, compression);
    } catch (const openvdb::Exception& e) {
        std::remove(tmp.c_str());
        throw Error(path + ": cannot write OpenVDB file: " + e.what());
    } catch (...) {
        std::remove(tmp.c_str());
        throw;
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::remove(tmp.c_str());
        throw Error(path + ": cannot rename the finished file into place: " + ec.message());
    }
    // The rename itself is durable only once the directory is synced.
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    fsyncPath(parent.empty() ? "." : parent.string(), O_RDONLY | O_DIRECTORY);
    if (options.timings) {
        const auto end = std::chrono::steady_clock::now();
        options.timings->treeSeconds += std::chrono::duration<double>(written - start).count();
        options.timings->writeSeconds += std::chrono::duration<double>(end - written).count();
    }
}

void writeVdb(const std::string& path, const BrickVolume& volume, const VolumeMetadata& metadata,
              const VdbWriteOptions& options) {
    VdbAssembler assembler(volume.grid, volume.reduce);
    assembler.add(volume.bricks);
    assembler.write(path, metadata, options);
}

} // namespace yv

#include "vdb/openvdb_encoding.h"

#include "core/brick_mask.h"
#include "core/error.h"
#include "core/half_floats.h"

#include <openvdb/io/Compression.h>
#include <openvdb/io/DelayedLoadMetadata.h>
#include <openvdb/io/GridDescriptor.h>
#include <openvdb/math/Half.h>
#include <openvdb/tools/Count.h>
#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <iterator>
#include <ostream>
#include <sstream>
#include <streambuf>

namespace yv {
namespace {

using DensityTree = openvdb::FloatGrid::TreeType;
using OrientationTree = openvdb::Vec3SGrid::TreeType;
using LeafMask = openvdb::util::NodeMask<3>;

/// A stream buffer that appends to a byte vector: OpenVDB's writers take an
/// ostream, and an ostringstream would copy every leaf once more.
class AppendBuffer : public std::streambuf {
  public:
    void target(ByteVector* out) { out_ = out; }

  protected:
    std::streamsize xsputn(const char* s, std::streamsize n) override {
        out_->insert(out_->end(), reinterpret_cast<const std::uint8_t*>(s), reinterpret_cast<const std::uint8_t*>(s) + n);
        return n;
    }
    int_type overflow(int_type c) override {
        if (!traits_type::eq_int_type(c, traits_type::eof())) out_->push_back(std::uint8_t(c));
        return traits_type::not_eof(c);
    }

  private:
    ByteVector* out_ = nullptr;
};

/// An ostream tagged the way OpenVDB's value writers expect: compression
/// flags and the grid's background value.
struct TaggedStream {
    AppendBuffer buffer;
    std::ostream os{&buffer};
    TaggedStream(std::uint32_t compression, const void* background) {
        openvdb::io::setDataCompression(os, compression);
        openvdb::io::setGridBackgroundValuePtr(os, background);
    }
};

const float kDensityBackground = 0.0f;
const openvdb::Vec3s kOrientationBackground(0.0f);

const void* backgroundOf(GridKind kind) {
    return kind == GridKind::Density ? static_cast<const void*>(&kDensityBackground)
                                     : static_cast<const void*>(&kOrientationBackground);
}

/// Exposes the protected pieces of OpenVDB's archive writer that yarnvox
/// reuses as they are: the header with its UUID, and the per-grid choice of compression.
class ArchivePieces : public openvdb::io::Archive {
  public:
    void header(std::ostream& os) const { writeHeader(os, /*seekable=*/true); }
    void compressionOf(std::ostream& os, const openvdb::GridBase& grid) const { setGridCompression(os, grid); }
};

/// Bytes of memory OpenVDB reports for a tree (tools::memUsage), per node:
/// measured on small trees so the numbers are OpenVDB's own.
template <typename TreeT> struct NodeMemory {
    std::uint64_t root = 0, upper = 0, lower = 0, leaf = 0;
    NodeMemory() {
        const auto usage = [](std::initializer_list<openvdb::Coord> voxels) {
            TreeT tree;
            for (const openvdb::Coord& c : voxels) tree.setValueOn(c);
            return std::uint64_t(openvdb::tools::memUsage(tree, /*threaded=*/false));
        };
        const std::uint64_t one = usage({{0, 0, 0}});
        leaf = usage({{0, 0, 0}, {8, 0, 0}}) - one;
        lower = usage({{0, 0, 0}, {128, 0, 0}}) - one - leaf;
        upper = usage({{0, 0, 0}, {4096, 0, 0}}) - one - lower - leaf;
        root = one - upper - lower - leaf;
    }
    std::uint64_t of(const GridStatistics& s) const {
        return root + s.upperNodes * upper + s.lowerNodes * lower + s.leaves * leaf;
    }
};

std::uint64_t memoryOf(GridKind kind, const GridStatistics& stats) {
    if (kind == GridKind::Density) {
        static const NodeMemory<DensityTree> m;
        return m.of(stats);
    }
    static const NodeMemory<OrientationTree> m;
    return m.of(stats);
}

template <typename T> void appendRaw(ByteVector& out, const T& value) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(&value);
    out.insert(out.end(), p, p + sizeof(T));
}

template <typename ValueT, openvdb::Index Log2Dim>
ByteVector internalValues(const GridEncoding& encoding) {
    using Mask = openvdb::util::NodeMask<Log2Dim>;
    constexpr openvdb::Index kCount = Mask::SIZE;
    std::vector<ValueT> values(kCount, openvdb::zeroVal<ValueT>());
    ByteVector out;
    TaggedStream s(encoding.compression, backgroundOf(encoding.kind));
    s.buffer.target(&out);
    openvdb::io::writeCompressedValues(s.os, values.data(), kCount, Mask(), Mask(), encoding.half);
    return out;
}

} // namespace

struct LeafEncoder::Impl {
    GridEncoding encoding;
    mutable tbb::enumerable_thread_specific<std::unique_ptr<TaggedStream>> streams;
};

LeafEncoder::LeafEncoder(const GridEncoding& encoding) : impl_(std::make_unique<Impl>()) { impl_->encoding = encoding; }
LeafEncoder::~LeafEncoder() = default;

namespace {

/// Mask compression without a codec (--vdb-compression mask, the default) in
/// the grid's and the file's flags: a leaf's record is then its mask, one
/// metadata byte and its active values, raw.
bool isPlainMaskRecord(const GridEncoding& encoding) {
    constexpr std::uint32_t kCodecs = openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_BLOSC;
    return (encoding.compression & openvdb::io::COMPRESS_ACTIVE_MASK) != 0 && (encoding.compression & kCodecs) == 0 &&
           (encoding.archiveCompression & kCodecs) == 0;
}

/// The record of one leaf's values, and what the delayed-load metadata says of it.
template <typename ValueT>
LeafLoadInfo encodeValues(std::ostream& os, ValueT* values, const LeafMask& mask, const GridEncoding& encoding) {
    const ValueT background = openvdb::zeroVal<ValueT>();
    const openvdb::io::MaskCompress<ValueT, LeafMask> compressed(mask, LeafMask(), values, background);
    LeafLoadInfo info;
    info.maskMetadata = std::int8_t(compressed.metadata);
    if (encoding.archiveCompression & (openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ZIP))
        info.compressedBytes = std::int64_t(openvdb::io::writeCompressedValuesSize(
                                   values, kBrickVoxels, mask, std::uint8_t(compressed.metadata), encoding.half,
                                   encoding.archiveCompression)) +
                               8;
    openvdb::io::writeCompressedValues(os, values, kBrickVoxels, mask, LeafMask(), encoding.half);
    return info;
}

/// One leaf's buffer record, as LeafNode::writeBuffers writes it: the value
/// mask `words`, then the values, which active voxel v (the n-th active one,
/// from 0) takes from `density(v, n)` or `vector(v, n)`, and the others the
/// background. `stream` is the calling thread's, made on first use.
template <class DensityAt, class VectorAt>
LeafLoadInfo encodeLeaf(std::unique_ptr<TaggedStream>& stream, const GridEncoding& encoding,
                        const std::array<std::uint64_t, kBrickVoxels / 64>& words, ByteVector& out, DensityAt density,
                        VectorAt vector) {
    const auto eachActive = [&](auto&& put) {
        std::size_t n = 0;
        for (int w = 0; w < kBrickVoxels / 64; ++w)
            for (std::uint64_t bits = words[w]; bits; bits &= bits - 1, ++n) put(w * 64 + std::countr_zero(bits), n);
    };
    if (isPlainMaskRecord(encoding)) {
        // The record writeCompressedValues makes when every inactive value is
        // the background (yarnvox's always is): the mask, the metadata byte,
        // the active values in voxel order. Written directly: OpenVDB's
        // writer fills and scans all 512 values (6 KiB for a vector) and
        // goes through a stream, several times the cost of the bytes.
        const std::size_t active = std::size_t(activeVoxelCount(words));
        const std::size_t components = encoding.kind == GridKind::Density ? 1 : 3;
        const std::size_t at = out.size();
        out.resize(at + sizeof words + 1 + active * components * (encoding.half ? 2 : 4));
        std::uint8_t* p = out.data() + at;
        std::memcpy(p, words.data(), sizeof words);
        p += sizeof words;
        *p++ = std::uint8_t(openvdb::io::NO_MASK_OR_INACTIVE_VALS);
        // The active values gathered, then stored: as halves eight at a time
        // (core/half_floats.h: OpenVDB's rounding), or as they are.
        float values[3 * kBrickVoxels];
        std::size_t count = 0;
        if (encoding.kind == GridKind::Density) {
            eachActive([&](int v, std::size_t n) { values[count++] = density(v, n); });
        } else {
            eachActive([&](int v, std::size_t n) {
                const openvdb::Vec3s value = vector(v, n);
                values[count++] = value[0];
                values[count++] = value[1];
                values[count++] = value[2];
            });
        }
        if (encoding.half)
            floatsToHalves(values, p, count);
        else
            std::memcpy(p, values, count * sizeof(float));
        LeafLoadInfo info;
        info.maskMetadata = std::int8_t(openvdb::io::NO_MASK_OR_INACTIVE_VALS);
        return info;
    }
    if (!stream) stream = std::make_unique<TaggedStream>(encoding.compression, backgroundOf(encoding.kind));
    stream->buffer.target(&out);
    LeafMask mask;
    for (int w = 0; w < kBrickVoxels / 64; ++w) mask.getWord<std::uint64_t>(w) = words[w];
    mask.save(stream->os);
    LeafLoadInfo info;
    if (encoding.kind == GridKind::Density) {
        float values[kBrickVoxels] = {};
        eachActive([&](int v, std::size_t n) { values[v] = density(v, n); });
        info = encodeValues(stream->os, values, mask, encoding);
    } else {
        openvdb::Vec3s values[kBrickVoxels];
        std::fill(std::begin(values), std::end(values), openvdb::Vec3s(0.0f));
        eachActive([&](int v, std::size_t n) { values[v] = vector(v, n); });
        info = encodeValues(stream->os, values, mask, encoding);
    }
    if (!stream->os) throw Error("encoding a leaf for the .vdb failed");
    return info;
}

} // namespace

LeafLoadInfo LeafEncoder::encode(const VoxelBrick& brick, ByteVector& out) const {
    const GridEncoding& encoding = impl_->encoding;
    if (encoding.kind == GridKind::Albedo && brick.albedo.size() != std::size_t(kBrickVoxels))
        throw Error("brick " + std::to_string(brick.key) + " has no albedo for the .vdb's albedo grid");
    const glm::vec3* source = encoding.kind == GridKind::Albedo ? brick.albedo.data() : brick.orientation.data();
    return encodeLeaf(
        impl_->streams.local(), encoding, brick.activeMask, out, [&](int v, std::size_t) { return brick.density[v]; },
        [&](int v, std::size_t) { return openvdb::Vec3s(source[v].x, source[v].y, source[v].z); });
}

LeafLoadInfo LeafEncoder::encode(const PackedBricks& packed, std::size_t i,
                                 const std::array<std::uint64_t, kBrickVoxels / 64>& maskWords, ByteVector& out) const {
    const GridEncoding& encoding = impl_->encoding;
    const bool albedo = encoding.kind == GridKind::Albedo;
    if (albedo && packed.albedo.size() != packed.voxels.size())
        throw Error("brick " + std::to_string(packed.headers[i].brickKey()) + " has no albedo for the .vdb's albedo grid");
    // The active voxels follow each other in voxel order from firstVoxel.
    const std::size_t first = packed.headers[i].firstVoxel;
    return encodeLeaf(
        impl_->streams.local(), encoding, maskWords, out,
        [&](int, std::size_t n) { return packed.voxels[first + n].density; },
        [&](int, std::size_t n) {
            const float* a = albedo ? packed.albedo[first + n].rgb : packed.voxels[first + n].axis;
            return openvdb::Vec3s(a[0], a[1], a[2]);
        });
}

std::string gridName(GridKind kind, int lodLevel) {
    const std::string base =
        kind == GridKind::Density ? "density" : (kind == GridKind::Orientation ? "orientation" : "albedo");
    return lodLevel == 0 ? base : base + "_lod" + std::to_string(lodLevel);
}

openvdb::GridBase::Ptr makeSkeletonGrid(GridKind kind, const openvdb::math::Transform::Ptr& transform, bool half,
                                        int lodLevel) {
    openvdb::GridBase::Ptr grid;
    if (kind == GridKind::Density) {
        grid = openvdb::FloatGrid::create(0.0f);
        grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    } else {
        grid = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
        // An axis or a colour: not transformed like a position.
        grid->setVectorType(openvdb::VEC_INVARIANT);
        if (kind == GridKind::Albedo) grid->insertMeta("color_space", openvdb::StringMetadata("linear"));
    }
    grid->setName(gridName(kind, lodLevel));
    if (lodLevel > 0) grid->insertMeta("lod_level", openvdb::Int32Metadata(lodLevel));
    grid->setTransform(transform);
    grid->setSaveFloatAsHalf(half);
    return grid;
}

std::uint32_t gridCompression(std::uint32_t archiveFlags, const openvdb::GridBase& skeleton) {
    ArchivePieces archive;
    archive.setCompression(archiveFlags);
    std::ostringstream scratch(std::ios::binary);
    archive.compressionOf(scratch, skeleton);
    return openvdb::io::getDataCompression(scratch);
}

ByteVector fileHeaderBytes(const openvdb::MetaMap& fileMetadata, std::int32_t gridCount) {
    std::ostringstream os(std::ios::binary);
    ArchivePieces().header(os);
    fileMetadata.writeMeta(os);
    os.write(reinterpret_cast<const char*>(&gridCount), sizeof gridCount);
    const std::string s = os.str();
    return ByteVector(s.begin(), s.end());
}

ByteVector gridPrefixBytes(const openvdb::GridBase& skeleton, const GridEncoding& encoding,
                           const GridStatistics& stats, std::span<const LeafLoadInfo> leaves,
                           std::size_t& positionsAt) {
    std::ostringstream os(std::ios::binary);
    const openvdb::io::GridDescriptor descriptor(skeleton.getName(), skeleton.type(), encoding.half);
    descriptor.writeHeader(os);
    positionsAt = std::size_t(os.tellp());
    descriptor.writeStreamPos(os); // placeholders, patched once the layout is known
    os.write(reinterpret_cast<const char*>(&encoding.compression), sizeof encoding.compression);

    openvdb::MetaMap meta = static_cast<const openvdb::MetaMap&>(skeleton);
    using openvdb::GridBase;
    meta.insertMeta(GridBase::META_FILE_BBOX_MIN, openvdb::Vec3IMetadata(stats.activeBounds.min().asVec3i()));
    meta.insertMeta(GridBase::META_FILE_BBOX_MAX, openvdb::Vec3IMetadata(stats.activeBounds.max().asVec3i()));
    meta.insertMeta(GridBase::META_FILE_MEM_BYTES,
                    openvdb::Int64Metadata(static_cast<std::int64_t>(memoryOf(encoding.kind, stats))));
    meta.insertMeta(GridBase::META_FILE_VOXEL_COUNT,
                    openvdb::Int64Metadata(static_cast<std::int64_t>(stats.activeVoxels)));
    meta.insertMeta(GridBase::META_FILE_COMPRESSION,
                    openvdb::StringMetadata(openvdb::io::compressionToString(encoding.compression)));
    auto delayedLoad = std::make_shared<openvdb::io::DelayedLoadMetadata>();
    if (!leaves.empty()) {
        delayedLoad->resizeMask(leaves.size());
        const bool sized = encoding.archiveCompression & (openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ZIP);
        if (sized) delayedLoad->resizeCompressedSize(leaves.size());
        for (std::size_t i = 0; i < leaves.size(); ++i) {
            delayedLoad->setMask(i, leaves[i].maskMetadata);
            if (sized) delayedLoad->setCompressedSize(i, leaves[i].compressedBytes);
        }
    }
    meta.insertMeta(GridBase::META_FILE_DELAYED_LOAD, *delayedLoad);
    meta.writeMeta(os);
    skeleton.writeTransform(os);
    const std::string s = os.str();
    return ByteVector(s.begin(), s.end());
}

void patchStreamPositions(ByteVector& prefix, std::size_t positionsAt, const openvdb::GridBase& skeleton,
                          bool half, std::int64_t gridPos, std::int64_t blockPos, std::int64_t endPos) {
    openvdb::io::GridDescriptor descriptor(skeleton.getName(), skeleton.type(), half);
    descriptor.setGridPos(gridPos);
    descriptor.setBlockPos(blockPos);
    descriptor.setEndPos(endPos);
    std::ostringstream os(std::ios::binary);
    descriptor.writeStreamPos(os);
    const std::string s = os.str();
    YV_CHECK(positionsAt + s.size() <= prefix.size());
    std::memcpy(prefix.data() + positionsAt, s.data(), s.size());
}

ByteVector treeTopologyHeader(const GridEncoding& encoding, std::uint32_t rootChildren) {
    ByteVector out;
    appendRaw(out, std::int32_t(1)); // buffer count
    if (encoding.kind == GridKind::Density)
        appendRaw(out, kDensityBackground); // zero: the same as half
    else
        appendRaw(out, kOrientationBackground);
    appendRaw(out, std::uint32_t(0)); // tiles
    appendRaw(out, rootChildren);
    return out;
}

ByteVector internalNodeValues(const GridEncoding& encoding, int log2Dim) {
    YV_CHECK(log2Dim == 4 || log2Dim == 5);
    if (encoding.kind == GridKind::Density)
        return log2Dim == 5 ? internalValues<float, 5>(encoding) : internalValues<float, 4>(encoding);
    return log2Dim == 5 ? internalValues<openvdb::Vec3s, 5>(encoding) : internalValues<openvdb::Vec3s, 4>(encoding);
}

} // namespace yv

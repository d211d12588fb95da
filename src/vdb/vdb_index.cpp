#include "vdb/vdb_index.h"

#include "core/error.h"
#include "core/text.h"
#include "vdb/openvdb_encoding.h"

#include <openvdb/openvdb.h>

#include <bit>
#include <sstream>

namespace yv {
namespace {

constexpr std::int64_t kMagic = 0x56444220;
constexpr std::uint32_t kFileVersion = 224;
constexpr std::uint32_t kMaxGrids = 4096;
constexpr std::uint32_t kMaxMetadataItems = 1u << 16;
constexpr std::uint32_t kMaxMetadataBytes = 1u << 30; // file_delayed_load: a few bytes per leaf
constexpr std::uint32_t kMaskCompression = 0x2;       // io::COMPRESS_ACTIVE_MASK
constexpr std::size_t kUpperMaskBytes = 4096, kLowerMaskBytes = 512, kLeafMaskBytes = 64;

std::vector<StoredMetadata> readMetadataMap(FileCursor& in, const std::string& what, bool keepDelayedLoad = false) {
    const auto count = in.pod<std::uint32_t>(what + " item count");
    if (count > kMaxMetadataItems)
        throw Error(in.where() + what + " declares " + std::to_string(count) + " items (damaged?)");
    std::vector<StoredMetadata> items;
    for (std::uint32_t i = 0; i < count; ++i) {
        StoredMetadata m;
        m.name = in.string(what + " item name", 1u << 16);
        const std::string item = what + " item '" + shownName(m.name) + "'";
        m.type = in.string(item + " type", 1u << 10);
        const auto bytes = in.pod<std::uint32_t>(item + " size");
        if (bytes > kMaxMetadataBytes)
            throw Error(in.where() + item + " declares " + std::to_string(bytes) + " bytes (damaged?)");
        if (m.name == openvdb::GridBase::META_FILE_DELAYED_LOAD && !keepDelayedLoad) {
            in.skip(bytes);
            continue;
        }
        const auto value = in.bytes(bytes, item);
        m.value.assign(value.begin(), value.end());
        items.push_back(std::move(m));
    }
    return items;
}

std::int32_t int32Of(const StoredMetadata& m) {
    std::int32_t v = 0;
    if (m.type == "int32" && m.value.size() == sizeof v) std::memcpy(&v, m.value.data(), sizeof v);
    return v;
}

/// Expected bytes of an internal node's value record in a yarnvox file.
struct NodeRecords {
    ByteVector upper, lower;
};

NodeRecords nodeRecordsOf(const VdbGridInfo& g) {
    GridEncoding e;
    e.kind = g.vector ? GridKind::Orientation : GridKind::Density;
    e.compression = g.compression;
    e.archiveCompression = g.compression;
    e.half = g.half;
    return {internalNodeValues(e, 5), internalNodeValues(e, 4)};
}

std::string gridWhat(const VdbGridInfo& g) { return "grid '" + shownName(g.name) + "'"; }

} // namespace

std::string StoredMetadata::text() const {
    openvdb::initialize();
    try {
        const openvdb::Metadata::Ptr m = openvdb::Metadata::createMetadata(type);
        std::string bytes(sizeof(std::uint32_t), '\0');
        const auto size = std::uint32_t(value.size());
        std::memcpy(bytes.data(), &size, sizeof size);
        bytes.append(reinterpret_cast<const char*>(value.data()), value.size());
        std::istringstream is(bytes, std::ios::binary);
        m->read(is);
        if (is) return m->str();
    } catch (const openvdb::Exception&) {
    }
    return "<" + std::to_string(value.size()) + " bytes of " + type + ">";
}

const StoredMetadata* VdbGridInfo::find(const std::string& wanted) const {
    for (const StoredMetadata& m : metadata)
        if (m.name == wanted) return &m;
    return nullptr;
}

VdbIndex::VdbIndex(const std::string& path) : file_(std::make_unique<ReadOnlyFile>(path)) {
    FileCursor in(*file_, 0, 1u << 20);
    if (file_->size() < 8 || in.pod<std::int64_t>("magic") != kMagic)
        throw Error(path + ": not an OpenVDB file (no VDB magic number at its start)");
    const auto version = in.pod<std::uint32_t>("file format version");
    const auto major = in.pod<std::uint32_t>("library major version");
    const auto minor = in.pod<std::uint32_t>("library minor version");
    libraryVersion_ = std::to_string(major) + "." + std::to_string(minor) + "/" + std::to_string(version);
    if (version != kFileVersion) {
        whyNotSubset_ = "file format version " + std::to_string(version) + ", not 224";
        return; // the rest of the header depends on the version: OpenVDB reads it
    }
    const auto offsets = in.pod<std::uint8_t>("grid offsets flag");
    in.skip(36); // UUID
    fileMetadata_ = readMetadataMap(in, "file metadata");
    const auto count = in.pod<std::int32_t>("grid count");
    if (count < 0 || std::uint32_t(count) > kMaxGrids)
        throw Error(in.where() + "grid count " + std::to_string(count) + " (damaged?)");
    gridsPos_ = in.position();
    gridCount_ = std::uint32_t(count);
    if (offsets != 1) whyNotSubset_ = "grids without stream offsets";
    bool yarnvox = false;
    for (const StoredMetadata& m : fileMetadata_) yarnvox = yarnvox || m.name == "yarnvox_version";
    if (!yarnvox && whyNotSubset_.empty()) whyNotSubset_ = "not written by yarnvox";
    if (!whyNotSubset_.empty()) return;

    for (std::int32_t n = 0; n < count; ++n) {
        VdbGridInfo g;
        g.name = in.string("grid name", 1u << 16);
        g.type = in.string(gridWhat(g) + " type", 1u << 10);
        const std::string kHalf = "_HalfFloat";
        if (g.type.size() > kHalf.size() && g.type.ends_with(kHalf)) {
            g.half = true;
            g.type.resize(g.type.size() - kHalf.size());
        }
        in.string(gridWhat(g) + " instance parent", 1u << 16);
        const auto gridPos = in.pod<std::int64_t>(gridWhat(g) + " start");
        const auto blockPos = in.pod<std::int64_t>(gridWhat(g) + " leaf buffers' start");
        const auto endPos = in.pod<std::int64_t>(gridWhat(g) + " end");
        const std::uint64_t size = file_->size();
        // The grid's data may start past its descriptor (zeros between: a
        // streamed file puts its records on a whole block), as OpenVDB seeks to it.
        if (gridPos < 0 || blockPos < gridPos || endPos < blockPos || std::uint64_t(endPos) > size ||
            std::uint64_t(gridPos) < in.position())
            throw Error(path + ": " + gridWhat(g) + ": its descriptor places it at bytes " + std::to_string(gridPos) +
                        ", " + std::to_string(blockPos) + " to " + std::to_string(endPos) + ", but the file has " +
                        std::to_string(size) + " bytes (truncated or damaged)");
        g.gridPos = std::uint64_t(gridPos), g.blockPos = std::uint64_t(blockPos), g.endPos = std::uint64_t(endPos);
        in.seek(g.gridPos);
        g.compression = in.pod<std::uint32_t>(gridWhat(g) + " compression");
        g.metadata = readMetadataMap(in, gridWhat(g) + " metadata");
        if (const StoredMetadata* lod = g.find("lod_level")) g.lodLevel = int32Of(*lod);
        const std::string map = in.string(gridWhat(g) + " transform type", 1u << 10);
        if (g.type == "Tree_vec3s_5_4_3")
            g.vector = true;
        else if (g.type != "Tree_float_5_4_3")
            whyNotSubset_ = gridWhat(g) + " of type " + g.type;
        if (map != "UniformScaleTranslateMap") whyNotSubset_ = gridWhat(g) + " with a " + map;
        if (g.compression != kMaskCompression) whyNotSubset_ = gridWhat(g) + " compressed other than by its mask alone";
        if (!whyNotSubset_.empty()) return;
        const auto maps = in.bytes(6 * sizeof(glm::dvec3), gridWhat(g) + " transform");
        glm::dvec3 translation, scale;
        std::memcpy(&translation, maps.data(), sizeof translation);
        std::memcpy(&scale, maps.data() + sizeof translation, sizeof scale);
        if (!(scale.x > 0.0) || scale.x != scale.y || scale.x != scale.z)
            throw Error(in.where() + gridWhat(g) + " has a transform of scale (" + std::to_string(scale.x) + ", " +
                        std::to_string(scale.y) + ", " + std::to_string(scale.z) + "), not a uniform positive one");
        g.voxelSize = scale.x;
        g.translation = translation;
        g.topologyPos = in.position();
        grids_.push_back(std::move(g));
        in.seek(std::uint64_t(endPos));
    }
}

const VdbGridInfo* VdbIndex::grid(const std::string& name) const {
    for (const VdbGridInfo& g : grids_)
        if (g.name == name) return &g;
    return nullptr;
}

VdbLeafTable VdbIndex::leaves(const VdbGridInfo& g) const {
    YV_CHECK(inSubset());
    FileCursor in(*file_, g.topologyPos);
    const std::string what = gridWhat(g);
    const auto fail = [&](const std::string& why) { throw Error(in.where() + what + ": " + why); };
    if (in.pod<std::int32_t>(what + " buffer count") != 1) fail("not one buffer per leaf");
    const std::size_t valueBytes = g.vector ? 12 : 4;
    const auto background = in.bytes(valueBytes, what + " background");
    for (std::uint8_t b : background)
        if (b != 0) fail("background is not 0");
    if (in.pod<std::uint32_t>(what + " root tile count") != 0) fail("the root has tiles");
    const auto children = in.pod<std::uint32_t>(what + " root child count");
    // Each root child takes at least its origin and two masks: a count the file cannot hold is damage.
    if (std::uint64_t(children) * (12 + 2 * kUpperMaskBytes) > g.blockPos - in.position())
        fail("root child count " + std::to_string(children) + " does not fit before the leaf buffers");
    const NodeRecords records = nodeRecordsOf(g);
    const std::uint64_t valueSize = (g.half ? 2 : 4) * (g.vector ? 3 : 1);

    VdbLeafTable table;
    std::uint64_t at = g.blockPos;
    const auto words = [](std::span<const std::uint8_t> bytes, std::size_t i) {
        std::uint64_t w;
        std::memcpy(&w, bytes.data() + 8 * i, 8);
        return w;
    };
    for (std::uint32_t c = 0; c < children; ++c) {
        glm::ivec3 upperOrigin;
        std::memcpy(&upperOrigin, in.bytes(12, what + " root child origin").data(), 12);
        if (glm::any(glm::notEqual(upperOrigin & 4095, glm::ivec3(0))) ||
            glm::any(glm::lessThan(upperOrigin, glm::ivec3(0))))
            fail("root child origin (" + std::to_string(upperOrigin.x) + ", " + std::to_string(upperOrigin.y) + ", " +
                 std::to_string(upperOrigin.z) + ") is not a non-negative multiple of 4096");
        const auto upperMaskBytes = in.bytes(kUpperMaskBytes, what + " 32^3 node child mask");
        const std::vector<std::uint8_t> upperMask(upperMaskBytes.begin(), upperMaskBytes.end());
        for (std::uint8_t b : in.bytes(kUpperMaskBytes, what + " 32^3 node value mask"))
            if (b != 0) fail("a 32^3 node has active tiles");
        const auto upperValues = in.bytes(records.upper.size(), what + " 32^3 node values");
        if (!std::equal(upperValues.begin(), upperValues.end(), records.upper.begin())) fail("a 32^3 node's tile values are not the background");
        for (std::size_t w = 0; w < kUpperMaskBytes / 8; ++w)
            for (std::uint64_t bits = words(upperMask, w); bits; bits &= bits - 1) {
                const int n = int(w * 64) + std::countr_zero(bits);
                const glm::ivec3 lowerOrigin = upperOrigin + glm::ivec3(n >> 10, (n >> 5) & 31, n & 31) * 128;
                const auto lowerMaskBytes = in.bytes(kLowerMaskBytes, what + " 16^3 node child mask");
                const std::vector<std::uint8_t> lowerMask(lowerMaskBytes.begin(), lowerMaskBytes.end());
                for (std::uint8_t b : in.bytes(kLowerMaskBytes, what + " 16^3 node value mask"))
                    if (b != 0) fail("a 16^3 node has active tiles");
                const auto lowerValues = in.bytes(records.lower.size(), what + " 16^3 node values");
                if (!std::equal(lowerValues.begin(), lowerValues.end(), records.lower.begin()))
                    fail("a 16^3 node's tile values are not the background");
                for (std::size_t lw = 0; lw < kLowerMaskBytes / 8; ++lw)
                    for (std::uint64_t leafBits = words(lowerMask, lw); leafBits; leafBits &= leafBits - 1) {
                        const int k = int(lw * 64) + std::countr_zero(leafBits);
                        const glm::ivec3 origin = lowerOrigin + glm::ivec3(k >> 8, (k >> 4) & 15, k & 15) * 8;
                        const auto mask = in.bytes(kLeafMaskBytes, what + " leaf value mask");
                        std::uint64_t active = 0;
                        for (std::size_t i = 0; i < kLeafMaskBytes / 8; ++i) active += std::popcount(words(mask, i));
                        if (active == 0) fail("leaf " + std::to_string(table.bricks.size()) + " has no active voxel");
                        table.bricks.push_back(origin / 8);
                        table.records.push_back(at);
                        at += kLeafMaskBytes + 1 + active * valueSize;
                        table.activeVoxels += active;
                    }
            }
    }
    if (in.position() != g.blockPos)
        fail("the topology ends at byte " + std::to_string(in.position()) + ", but the leaf buffers start at byte " +
             std::to_string(g.blockPos));
    if (at != g.endPos)
        throw Error(path() + ": " + what + ": its " + std::to_string(table.bricks.size()) + " leaves need records up to byte " +
                    std::to_string(at) + ", but the grid ends at byte " + std::to_string(g.endPos) + " (damaged)");
    table.records.push_back(at);
    return table;
}

} // namespace yv

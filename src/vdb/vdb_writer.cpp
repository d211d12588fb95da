#include "vdb/vdb_writer.h"

#include "core/atomic_file.h"
#include "core/default_init_allocator.h"
#include "core/error.h"
#include "core/text.h"
#include "core/trace.h"
#include "vdb/chunked_output.h"
#include "vdb/lod_pyramid.h"
#include "vdb/openvdb_encoding.h"
#include "vdb/spill_file.h"
#include "vdb/tree_order.h"

#include <openvdb/openvdb.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <thread>

namespace yv {
namespace {

double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

std::uint32_t archiveFlags(VdbCompression c) {
    switch (c) {
    case VdbCompression::Blosc: return openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK;
    case VdbCompression::Zip: return openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK;
    case VdbCompression::ActiveMask: return openvdb::io::COMPRESS_ACTIVE_MASK;
    case VdbCompression::None: return openvdb::io::COMPRESS_NONE;
    }
    return openvdb::io::COMPRESS_NONE;
}

/// Grids of one level at most: density, orientation, albedo (GridKind order).
constexpr int kMaxGrids = 3;

/// One leaf in the scratch file: where its records are (one per grid), and
/// its value mask (the topology needs every mask before the first buffer).
struct LeafRecord {
    std::uint64_t order = 0; ///< treeOrderKey
    std::uint64_t at[kMaxGrids] = {};
    std::uint32_t bytes[kMaxGrids] = {};
    std::uint32_t source = 0;
    LeafLoadInfo load[kMaxGrids]; ///< per grid, for the delayed-load metadata
    std::array<std::uint64_t, kBrickVoxels / 64> mask{};
};

/// Bricks are encoded in pieces of this many, so a large region never holds
/// all of its encoded bytes at once.
constexpr std::size_t kEncodePiece = 4096;
/// Leaves per write into the scratch file (encodeBatch): about 0.5 to 2 MB.
constexpr std::size_t kSpillBlock = 256;
/// Leaf records are indexed for the output's chunks in pieces of about this size.
constexpr std::uint64_t kRecordPieceBytes = 4ull << 20;

template <openvdb::Index Log2Dim> std::uint8_t* putMask(std::uint8_t* out, const openvdb::util::NodeMask<Log2Dim>& mask) {
    for (openvdb::Index w = 0; w < openvdb::util::NodeMask<Log2Dim>::WORD_COUNT; ++w) {
        const std::uint64_t word = mask.template getWord<std::uint64_t>(w);
        std::memcpy(out, &word, sizeof word);
        out += sizeof word;
    }
    return out;
}

std::uint8_t* putBytes(std::uint8_t* out, const void* p, std::size_t n) {
    std::memcpy(out, p, n);
    return out + n;
}

/// Bytes left uninitialized when sized: the topology is written whole, side by side.
using TopologyBytes = std::vector<std::uint8_t, DefaultInitAllocator<std::uint8_t>>;

/// One grid's topology (formats/vdb-subset.md) from records in tree order:
/// root children, their 32^3 and 16^3 internal nodes (child mask, an empty
/// value mask, the tile values), and each leaf's value mask. Where each node
/// goes is found in one pass over the leaves; the nodes are then written side
/// by side (at 8192 a grid's topology is about 1 GB).
TopologyBytes topologyBytes(const std::vector<LeafRecord>& leaves, const GridEncoding& encoding) {
    const ByteVector upperValues = internalNodeValues(encoding, 5);
    const ByteVector lowerValues = internalNodeValues(encoding, 4);
    constexpr std::size_t kUpperMaskBytes = openvdb::util::NodeMask<5>::WORD_COUNT * 8;
    constexpr std::size_t kLowerMaskBytes = openvdb::util::NodeMask<4>::WORD_COUNT * 8;
    // [begin, end) of the leaves under each root child and each 16^3 node, and where its bytes start.
    struct Node {
        std::size_t begin, end;
        std::uint64_t at;
    };
    std::vector<Node> upper, lower;
    std::uint64_t at = 0;
    for (std::size_t i = 0; i < leaves.size();) {
        const std::uint64_t root = rootChildOfOrder(leaves[i].order);
        Node u{i, i, at};
        at += 12 + 2 * kUpperMaskBytes + upperValues.size();
        while (u.end < leaves.size() && rootChildOfOrder(leaves[u.end].order) == root) {
            const std::uint64_t node = lowerNodeOfOrder(leaves[u.end].order);
            Node l{u.end, u.end, at};
            while (l.end < leaves.size() && lowerNodeOfOrder(leaves[l.end].order) == node) ++l.end;
            at += 2 * kLowerMaskBytes + lowerValues.size() + (l.end - l.begin) * sizeof(LeafRecord::mask);
            lower.push_back(l);
            u.end = l.end;
        }
        upper.push_back(u);
        i = u.end;
    }
    const ByteVector header = treeTopologyHeader(encoding, std::uint32_t(upper.size()));
    TopologyBytes out(header.size() + at);
    std::memcpy(out.data(), header.data(), header.size());
    std::uint8_t* const body = out.data() + header.size();
    tbb::parallel_for(std::size_t(0), upper.size(), [&](std::size_t n) {
        const Node& u = upper[n];
        openvdb::util::NodeMask<5> upperChildren;
        for (std::size_t i = u.begin; i < u.end; ++i) upperChildren.setOn(upperIndexOfOrder(leaves[i].order));
        const glm::ivec3 b = treeOrderCoord(leaves[u.begin].order);
        const std::int32_t origin[3] = {(b.x >> 9) << 12, (b.y >> 9) << 12, (b.z >> 9) << 12};
        std::uint8_t* p = putBytes(body + u.at, origin, sizeof origin);
        p = putMask(p, upperChildren);
        p = putMask(p, openvdb::util::NodeMask<5>());
        putBytes(p, upperValues.data(), upperValues.size());
    });
    tbb::parallel_for(std::size_t(0), lower.size(), [&](std::size_t n) {
        const Node& l = lower[n];
        openvdb::util::NodeMask<4> lowerChildren;
        for (std::size_t k = l.begin; k < l.end; ++k) lowerChildren.setOn(lowerIndexOfOrder(leaves[k].order));
        std::uint8_t* p = putMask(body + l.at, lowerChildren);
        p = putMask(p, openvdb::util::NodeMask<4>());
        p = putBytes(p, lowerValues.data(), lowerValues.size());
        for (std::size_t k = l.begin; k < l.end; ++k) p = putBytes(p, leaves[k].mask.data(), sizeof leaves[k].mask);
    });
    return out;
}

/// Consecutive leaf records of one grid, [begin, end) of its level's leaves
/// in tree order, at `at` in the output: the index that finds which records
/// a chunk of the output holds.
struct RecordPiece {
    const std::vector<LeafRecord>* leaves;
    int grid;
    std::size_t begin, end;
    std::uint64_t at, bytes;
};

/// Cuts one grid's records, laid out from `at`, into pieces of about kRecordPieceBytes.
void addRecordPieces(const std::vector<LeafRecord>& leaves, int grid, std::uint64_t at, std::vector<RecordPiece>& out) {
    for (std::size_t i = 0; i < leaves.size();) {
        RecordPiece p{&leaves, grid, i, i, at, 0};
        while (p.end < leaves.size() && (p.bytes == 0 || p.bytes + leaves[p.end].bytes[grid] <= kRecordPieceBytes))
            p.bytes += leaves[p.end++].bytes[grid];
        at += p.bytes;
        i = p.end;
        out.push_back(p);
    }
}

/// Fills out[0, n) with output bytes [at, at + n) from the records of
/// `pieces` (in file order) that overlap it: runs of records that follow
/// each other in the scratch file are read with one call.
void fillFromRecords(const std::vector<RecordPiece>& pieces, const SpillFile& spill, std::uint64_t at,
                     std::span<std::uint8_t> out) {
    const std::uint64_t end = at + out.size();
    auto piece = std::partition_point(pieces.begin(), pieces.end(),
                                      [&](const RecordPiece& p) { return p.at + p.bytes <= at; });
    for (; piece != pieces.end() && piece->at < end; ++piece) {
        const std::vector<LeafRecord>& leaves = *piece->leaves;
        const int g = piece->grid;
        std::uint64_t fileAt = piece->at;
        for (std::size_t i = piece->begin; i < piece->end && fileAt < end;) {
            // A run: records contiguous in the scratch file as in the output.
            const std::uint64_t from = leaves[i].at[g];
            std::uint64_t run = leaves[i].bytes[g];
            std::size_t j = i + 1;
            for (; j < piece->end && leaves[j].at[g] == from + run; ++j) run += leaves[j].bytes[g];
            const std::uint64_t lo = std::max(fileAt, at), hi = std::min(fileAt + run, end);
            if (lo < hi) spill.read(from + (lo - fileAt), out.subspan(lo - at, hi - lo));
            fileAt += run;
            i = j;
        }
    }
}

/// One level of the pyramid (0: the volume itself): its transform, its
/// grids' encodings (density, orientation, and albedo where the run has it),
/// and its leaves in the scratch file.
struct PyramidLevel {
    openvdb::math::Transform::Ptr transform;
    int gridCount = 2;
    openvdb::GridBase::Ptr skeleton[kMaxGrids];
    GridEncoding encoding[kMaxGrids];
    std::unique_ptr<LeafEncoder> encoders[kMaxGrids];
    std::vector<LeafRecord> leaves;
    openvdb::CoordBBox activeBounds;
    std::uint64_t activeVoxels = 0;
};

/// Where the octant a brick gives its parent lies in the scratch file
/// (lod_pyramid.h): 16 bytes per brick of the level below.
struct OctantRecord {
    std::uint64_t childKey = 0;
    std::uint64_t place = 0; ///< offset << 16 | bytes (an octant is at most 2056 bytes)
    std::uint64_t at() const { return place >> 16; }
    std::uint32_t bytes() const { return std::uint32_t(place & 0xffff); }
};

/// Leaves encoded from one batch of bricks, in tree order within the batch.
struct EncodedBatch {
    std::vector<LeafRecord> records;
    openvdb::CoordBBox bounds;
    std::uint64_t activeVoxels = 0;
};

using BrickMask = std::array<std::uint64_t, kBrickVoxels / 64>;

/// The bounds of a brick's active voxels (voxel v = x 64 + y 8 + z: word x
/// of the mask, byte y of the word, bit z of the byte), from its mask alone.
openvdb::CoordBBox activeBounds(std::uint64_t key, const BrickMask& mask) {
    int xMin = -1, xMax = -1;
    std::uint64_t yz = 0;
    for (int w = 0; w < kBrickVoxels / 64; ++w)
        if (mask[w]) {
            if (xMin < 0) xMin = w;
            xMax = w;
            yz |= mask[w];
        }
    if (xMin < 0) return {};
    int yMin = 8, yMax = -1;
    unsigned z = 0;
    for (int y = 0; y < 8; ++y)
        if (const unsigned byte = unsigned(yz >> (8 * y)) & 0xffu) {
            yMin = std::min(yMin, y);
            yMax = y;
            z |= byte;
        }
    const glm::ivec3 o = brickCoord(key) * kBrickSize;
    return {openvdb::Coord(o.x + xMin, o.y + yMin, o.z + std::countr_zero(z)),
            openvdb::Coord(o.x + xMax, o.y + yMax, o.z + 31 - std::countl_zero(z))};
}

/// The bricks encodeBatch takes: voxel bricks...
struct VoxelBrickBatch {
    std::span<const VoxelBrick> bricks;
    std::size_t size() const { return bricks.size(); }
    std::uint64_t key(std::size_t i) const { return bricks[i].key; }
    BrickMask mask(std::size_t i) const { return bricks[i].activeMask; }
    LeafLoadInfo encode(const LeafEncoder& encoder, std::size_t i, const BrickMask&, ByteVector& out) const {
        return encoder.encode(bricks[i], out);
    }
    void octant(std::size_t i, const BrickMask&, ByteVector& out) const { appendOctant(bricks[i], out); }
};

/// ... or the GPU's resolved bricks as they came back, packed: at 8192 filling
/// a VoxelBrick (8 KiB) per brick to encode it was 40 % of the writer
/// threads' time.
struct PackedBrickBatch {
    const PackedBricks& packed;
    std::size_t size() const { return packed.headers.size(); }
    std::uint64_t key(std::size_t i) const { return packed.headers[i].brickKey(); }
    BrickMask mask(std::size_t i) const { return packedBrickMask(packed, i); }
    LeafLoadInfo encode(const LeafEncoder& encoder, std::size_t i, const BrickMask& mask, ByteVector& out) const {
        return encoder.encode(packed, i, mask, out);
    }
    void octant(std::size_t i, const BrickMask& mask, ByteVector& out) const { appendOctant(packed, i, mask, out); }
};

/// Encodes `bricks` into leaf records of `level`'s grids in the scratch
/// file, in pieces; with `octants`, also puts each brick's octant for the
/// next level there.
template <typename Batch>
EncodedBatch encodeBatch(const PyramidLevel& level, SpillFile& spill, const Batch& bricks,
                         std::vector<OctantRecord>* octants) {
    // In tree order within the batch: the write then reads runs of neighbours with one call.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> order(bricks.size());
    for (std::size_t i = 0; i < bricks.size(); ++i) order[i] = {treeOrderKey(brickCoord(bricks.key(i))), std::uint32_t(i)};
    std::sort(order.begin(), order.end());

    EncodedBatch batch;
    batch.records.resize(bricks.size());
    for (std::size_t first = 0; first < bricks.size(); first += kEncodePiece) {
        const std::size_t count = std::min(kEncodePiece, bricks.size() - first);
        // Per grid, then the octants.
        constexpr int kOctants = kMaxGrids;
        std::vector<ByteVector> encoded[kMaxGrids + 1];
        for (auto& e : encoded) e.resize(count);
        std::vector<openvdb::CoordBBox> pieceBounds(count);
        std::vector<std::uint32_t> activeCounts(count);
        tbb::parallel_for(std::size_t(0), count, [&](std::size_t i) {
            const std::size_t b = order[first + i].second;
            LeafRecord& r = batch.records[first + i];
            r.mask = bricks.mask(b);
            for (int g = 0; g < level.gridCount; ++g) r.load[g] = bricks.encode(*level.encoders[g], b, r.mask, encoded[g][i]);
            if (octants) bricks.octant(b, r.mask, encoded[kOctants][i]);
            pieceBounds[i] = activeBounds(bricks.key(b), r.mask);
            for (std::uint64_t word : r.mask) activeCounts[i] += std::uint32_t(std::popcount(word));
        });
        // Each grid's piece (and the octants) in one range of the scratch
        // file, written in blocks on every core: joined and written by one
        // thread, a region's pieces were most of its encode time.
        std::vector<std::uint64_t> blockAt[kMaxGrids + 1]; // where each block of kSpillBlock leaves goes
        for (int g = 0; g <= kOctants; ++g) {
            if (g == kOctants ? !octants : g >= level.gridCount) continue;
            std::uint64_t at = 0;
            for (std::size_t i = 0; i < count; ++i) at += encoded[g][i].size();
            at = spill.reserve(at);
            for (std::size_t i = 0; i < count; ++i) {
                if (i % kSpillBlock == 0) blockAt[g].push_back(at);
                LeafRecord& r = batch.records[first + i];
                if (g == kOctants) {
                    YV_CHECK(encoded[g][i].size() < 0x10000);
                    octants->push_back({bricks.key(order[first + i].second), at << 16 | encoded[g][i].size()});
                } else {
                    r.at[g] = at;
                    r.bytes[g] = std::uint32_t(encoded[g][i].size());
                }
                at += encoded[g][i].size();
            }
        }
        const std::size_t blocks = (count + kSpillBlock - 1) / kSpillBlock;
        tbb::parallel_for(std::size_t(0), std::size_t(kOctants + 1) * blocks, [&](std::size_t task) {
            const int g = int(task / blocks);
            if (g == kOctants ? !octants : g >= level.gridCount) return;
            const std::size_t block = task % blocks, begin = block * kSpillBlock, end = std::min(count, begin + kSpillBlock);
            ByteVector joined;
            for (std::size_t i = begin; i < end; ++i) joined.insert(joined.end(), encoded[g][i].begin(), encoded[g][i].end());
            spill.writeAt(blockAt[g][block], joined);
        });
        for (std::size_t i = 0; i < count; ++i) {
            batch.records[first + i].order = order[first + i].first;
            batch.activeVoxels += activeCounts[i];
            if (!pieceBounds[i].empty()) batch.bounds.expand(pieceBounds[i]);
        }
    }
    return batch;
}

void addBatch(PyramidLevel& level, EncodedBatch&& batch, std::uint32_t source) {
    for (LeafRecord& r : batch.records) r.source = source;
    level.leaves.insert(level.leaves.end(), batch.records.begin(), batch.records.end());
    if (!batch.bounds.empty()) level.activeBounds.expand(batch.bounds);
    level.activeVoxels += batch.activeVoxels;
}

/// Coarse bricks are built in pieces of this many, so a level never holds
/// more than a piece of resolved bricks (about 8 MB).
constexpr std::size_t kPyramidPiece = 1024;

/// Builds `level` from the octants the bricks of the level below gave
/// (`octants`, sorted here by parent): each parent is its children's octants
/// put in place, then resolved and encoded; with `next`, each parent's own
/// octant for the level above goes to the scratch file and into `next`.
void buildLevel(PyramidLevel& level, SpillFile& spill, std::vector<OctantRecord>& octants,
                std::vector<OctantRecord>* next) {
    tbb::parallel_sort(octants.begin(), octants.end(), [](const OctantRecord& a, const OctantRecord& b) {
        const std::uint64_t pa = parentBrickKey(a.childKey), pb = parentBrickKey(b.childKey);
        return pa != pb ? pa < pb : a.childKey < b.childKey;
    });
    std::vector<std::size_t> groups; // where each parent's octants start
    for (std::size_t i = 0; i < octants.size(); ++i)
        if (i == 0 || parentBrickKey(octants[i].childKey) != parentBrickKey(octants[i - 1].childKey)) groups.push_back(i);
    groups.push_back(octants.size());
    const std::size_t parents = groups.size() - 1;

    tbb::enumerable_thread_specific<std::unique_ptr<CoarseBrick>> scratch;
    tbb::enumerable_thread_specific<ByteVector> buffers;
    std::vector<VoxelBrick> bricks;
    std::vector<ByteVector> nextOctants;
    std::vector<std::uint8_t> keep;
    for (std::size_t first = 0; first < parents; first += kPyramidPiece) {
        const std::size_t count = std::min(kPyramidPiece, parents - first);
        bricks.resize(count);
        keep.assign(count, 0);
        nextOctants.assign(next ? count : 0, ByteVector());
        tbb::parallel_for(std::size_t(0), count, [&](std::size_t i) {
            std::unique_ptr<CoarseBrick>& sums = scratch.local();
            if (!sums) sums = std::make_unique<CoarseBrick>();
            ByteVector& buffer = buffers.local();
            const std::size_t g = first + i;
            sums->clear(parentBrickKey(octants[groups[g]].childKey), level.gridCount > 2);
            for (std::size_t k = groups[g]; k < groups[g + 1]; ++k) {
                buffer.resize(octants[k].bytes());
                spill.read(octants[k].at(), buffer);
                placeOctant(buffer, octants[k].childKey, *sums);
            }
            keep[i] = resolveCoarseBrick(*sums, bricks[i]);
            if (next && keep[i]) appendOctant(*sums, bricks[i], nextOctants[i]);
        });
        if (next) {
            ByteVector joined;
            for (std::size_t i = 0; i < count; ++i) joined.insert(joined.end(), nextOctants[i].begin(), nextOctants[i].end());
            std::uint64_t at = spill.append(joined);
            for (std::size_t i = 0; i < count; ++i) {
                if (!keep[i]) continue;
                YV_CHECK(nextOctants[i].size() < 0x10000);
                next->push_back({bricks[i].key, at << 16 | nextOctants[i].size()});
                at += nextOctants[i].size();
            }
        }
        std::size_t kept = 0;
        for (std::size_t i = 0; i < count; ++i)
            if (keep[i]) {
                if (kept != i) bricks[kept] = bricks[i];
                ++kept;
            }
        addBatch(level, encodeBatch(level, spill, VoxelBrickBatch{std::span(bricks.data(), kept)}, nullptr), 0);
    }
}

} // namespace

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

const char* toString(VdbPrecision p) { return p == VdbPrecision::Half ? "half" : "float"; }

VdbPrecision parseVdbPrecision(const std::string& name) {
    if (name == "float") return VdbPrecision::Float;
    if (name == "half") return VdbPrecision::Half;
    throw Error("unknown --precision '" + name + "': expected float or half");
}

struct VdbAssembler::Impl {
    std::string path;
    VoxelGrid grid;
    Reduce reduce = Reduce::Mean;
    VdbWriteOptions options;
    std::vector<PyramidLevel> levels; ///< level 0, then --lod's coarser ones
    std::unique_ptr<SpillFile> spill;

    mutable std::mutex mutex;
    std::vector<OctantRecord> octants; ///< what each level-0 brick gives level 1 (with --lod)
    std::vector<std::string> sources;
    double encodeSeconds = 0.0;
    bool written = false;
};

VdbAssembler::VdbAssembler(std::string path, const VoxelGrid& grid, Reduce reduce, const VdbWriteOptions& options)
    : impl_(std::make_unique<Impl>()) {
    openvdb::initialize();
    Impl& m = *impl_;
    m.path = std::move(path);
    m.grid = grid;
    m.reduce = reduce;
    m.options = options;
    m.levels.resize(std::size_t(checkedLodLevels(options.lodLevels, grid)) + 1);
    for (PyramidLevel& level : m.levels) level.gridCount = options.albedo ? 3 : 2;
    const bool half = options.precision == VdbPrecision::Half;
    const std::uint32_t flags = archiveFlags(options.compression);
    for (std::size_t l = 0; l < m.levels.size(); ++l) {
        PyramidLevel& level = m.levels[l];
        // Level l's voxel (i, j, k) covers level 0's voxels 2^l (i, j, k) to 2^l (i + 1, j + 1, k + 1) - 1.
        const double h = grid.voxelSize * double(1u << l);
        level.transform = openvdb::math::Transform::createLinearTransform(h);
        const glm::dvec3 c = grid.origin + 0.5 * h;
        level.transform->postTranslate(openvdb::Vec3d(c.x, c.y, c.z));
        for (int g = 0; g < level.gridCount; ++g) {
            const auto kind = GridKind(g);
            level.skeleton[g] = makeSkeletonGrid(kind, level.transform, half, int(l));
            level.encoding[g] = {kind, gridCompression(flags, *level.skeleton[g]), flags, half};
            level.encoders[g] = std::make_unique<LeafEncoder>(level.encoding[g]);
        }
    }
    const std::filesystem::path dir = std::filesystem::path(m.path).parent_path();
    m.spill = std::make_unique<SpillFile>(dir.string(), "the OpenVDB file " + m.path + " (its leaves, before they are put in order)");
}

VdbAssembler::~VdbAssembler() = default;

void VdbAssembler::add(std::span<const VoxelBrick> bricks, const std::string& source) {
    addBatchOf(VoxelBrickBatch{bricks}, source);
}

void VdbAssembler::add(const PackedBricks& bricks, const std::string& source) {
    addBatchOf(PackedBrickBatch{bricks}, source);
}

template <typename Batch> void VdbAssembler::addBatchOf(const Batch& bricks, const std::string& source) {
    const TraceSpan span("encode leaves");
    Impl& m = *impl_;
    const auto start = std::chrono::steady_clock::now();
    std::vector<OctantRecord> octants;
    EncodedBatch batch = encodeBatch(m.levels[0], *m.spill, bricks, m.levels.size() > 1 ? &octants : nullptr);
    const double seconds = secondsSince(start);
    std::lock_guard lock(m.mutex);
    YV_CHECK(!m.written);
    const auto tag = static_cast<std::uint32_t>(m.sources.size());
    m.sources.push_back(source);
    addBatch(m.levels[0], std::move(batch), tag);
    m.octants.insert(m.octants.end(), octants.begin(), octants.end());
    m.encodeSeconds += seconds;
}

std::size_t VdbAssembler::brickCount() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->levels[0].leaves.size();
}

void VdbAssembler::write(const VolumeMetadata& metadata) {
    Impl& m = *impl_;
    const std::string& path = m.path;
    const auto start = std::chrono::steady_clock::now();
    std::lock_guard lock(m.mutex);
    YV_CHECK(!m.written);
    m.written = true;
    const auto treeOrder = [](const LeafRecord& a, const LeafRecord& b) {
        return a.order != b.order ? a.order < b.order : a.source < b.source;
    };
    tbb::parallel_sort(m.levels[0].leaves.begin(), m.levels[0].leaves.end(), treeOrder);
    traceSpanSince("sort the leaves", start);
    for (std::size_t i = 1; i < m.levels[0].leaves.size(); ++i) {
        const std::vector<LeafRecord>& leaves = m.levels[0].leaves;
        if (leaves[i].order == leaves[i - 1].order) {
            const std::string& a = m.sources[leaves[i - 1].source];
            const std::string& b = m.sources[leaves[i].source];
            const std::string from = a.empty() && b.empty() ? "" : " (from " + a + " and " + b + ")";
            throw Error(path + ": brick at voxel " + coordText(treeOrderCoord(leaves[i].order) * kBrickSize) +
                        " given twice" + from + ": cannot build one volume");
        }
    }
    // The pyramid, level by level from the octants each level's bricks left
    // in the scratch file: only the octants' places are held.
    const auto pyramidStart = std::chrono::steady_clock::now();
    std::vector<OctantRecord> octants = std::move(m.octants), next;
    for (std::size_t l = 1; l < m.levels.size(); ++l) {
        buildLevel(m.levels[l], *m.spill, octants, l + 1 < m.levels.size() ? &next : nullptr);
        std::vector<OctantRecord>().swap(octants);
        std::swap(octants, next);
        tbb::parallel_sort(m.levels[l].leaves.begin(), m.levels[l].leaves.end(), treeOrder);
    }
    const double pyramidSeconds = secondsSince(pyramidStart);
    m.encodeSeconds += pyramidSeconds;

    const VoxelGrid& grid = m.grid;
    openvdb::MetaMap fileMeta;
    fileMeta.insertMeta("yarnvox_version", openvdb::StringMetadata(YV_VERSION));
    fileMeta.insertMeta("input", openvdb::StringMetadata(metadata.input));
    fileMeta.insertMeta("backend", openvdb::StringMetadata(metadata.backend));
    fileMeta.insertMeta("cross_section", openvdb::StringMetadata(metadata.crossSection));
    fileMeta.insertMeta("resolution", openvdb::Int32Metadata(metadata.resolution));
    fileMeta.insertMeta("voxel_size", openvdb::DoubleMetadata(grid.voxelSize));
    fileMeta.insertMeta("reduce", openvdb::StringMetadata(toString(m.reduce)));
    fileMeta.insertMeta("slice_count", openvdb::Int64Metadata(static_cast<std::int64_t>(metadata.sliceCount)));
    fileMeta.insertMeta("yarn_radius", openvdb::DoubleMetadata(metadata.yarnRadius));
    fileMeta.insertMeta("yarn_radius_source", openvdb::StringMetadata(metadata.yarnRadiusSource));
    fileMeta.insertMeta("twist", openvdb::DoubleMetadata(metadata.twist));
    fileMeta.insertMeta("supersample", openvdb::Int32Metadata(metadata.supersample));
    fileMeta.insertMeta("overlap", openvdb::StringMetadata(metadata.overlap));
    fileMeta.insertMeta("slice_spacing", openvdb::DoubleMetadata(metadata.sliceSpacing));
    // How the slices were placed, so `inspect --render slices` places them again.
    fileMeta.insertMeta("slices_per_segment", openvdb::Int32Metadata(metadata.slicesPerSegment));
    fileMeta.insertMeta("slice_spacing_option", openvdb::DoubleMetadata(metadata.sliceSpacingOption));
    fileMeta.insertMeta("grid_dims", openvdb::Vec3IMetadata(openvdb::Vec3i(grid.dims.x, grid.dims.y, grid.dims.z)));
    if (m.levels.size() > 1) fileMeta.insertMeta("lod_levels", openvdb::Int32Metadata(int(m.levels.size()) - 1));
    if (m.levels[0].gridCount > 2) fileMeta.insertMeta("albedo", openvdb::StringMetadata("linear RGB, density-weighted mean"));

    // Zoom regions on the density grid, not the file: a summary lists the
    // file's items, and a large run has thousands of regions.
    if (!metadata.regions.empty())
        m.levels[0].skeleton[0]->insertMeta(kRegionsMetadataName, openvdb::StringMetadata(encodeRegions(metadata.regions)));

    // The layout: header, then per grid (level by level, density, orientation
    // and albedo) its prefix, topology and leaf records.
    std::vector<std::pair<std::size_t, int>> gridOf; // (level, grid) of each grid in the file
    for (std::size_t l = 0; l < m.levels.size(); ++l)
        for (int g = 0; g < m.levels[l].gridCount; ++g) gridOf.emplace_back(l, g);
    const std::size_t gridCount = gridOf.size();
    const ByteVector header = fileHeaderBytes(fileMeta, std::int32_t(gridCount));
    std::vector<ByteVector> prefix(gridCount);
    std::vector<TopologyBytes> topology(gridCount);
    std::vector<std::size_t> positionsAt(gridCount);
    std::vector<std::uint64_t> gridStart(gridCount), recordsAt(gridCount), recordBytes(gridCount);
    std::vector<GridStatistics> levelStats(m.levels.size());
    for (std::size_t l = 0; l < m.levels.size(); ++l) {
        const PyramidLevel& level = m.levels[l];
        const std::vector<LeafRecord>& leaves = level.leaves;
        GridStatistics& stats = levelStats[l];
        stats.activeBounds = level.activeBounds;
        stats.activeVoxels = level.activeVoxels;
        stats.leaves = leaves.size();
        std::uint64_t bytes[kMaxGrids] = {};
        for (std::size_t i = 0; i < leaves.size(); ++i) {
            YV_CHECK(i == 0 || leaves[i].order != leaves[i - 1].order);
            stats.upperNodes += i == 0 || rootChildOfOrder(leaves[i].order) != rootChildOfOrder(leaves[i - 1].order);
            stats.lowerNodes += i == 0 || lowerNodeOfOrder(leaves[i].order) != lowerNodeOfOrder(leaves[i - 1].order);
            for (int g = 0; g < level.gridCount; ++g) bytes[g] += leaves[i].bytes[g];
        }
        for (std::size_t n = 0; n < gridCount; ++n)
            if (gridOf[n].first == l) recordBytes[n] = bytes[gridOf[n].second];
    }
    // Each grid's prefix and topology, side by side: neither depends on where the grid lands.
    tbb::parallel_for(std::size_t(0), gridCount, [&](std::size_t n) {
        const auto [l, g] = gridOf[n];
        const PyramidLevel& level = m.levels[l];
        std::vector<LeafLoadInfo> load(level.leaves.size());
        for (std::size_t i = 0; i < level.leaves.size(); ++i) load[i] = level.leaves[i].load[g];
        prefix[n] = gridPrefixBytes(*level.skeleton[g], level.encoding[g], levelStats[l], load, positionsAt[n]);
        topology[n] = topologyBytes(level.leaves, level.encoding[g]);
    });
    std::uint64_t at = header.size();
    for (std::size_t n = 0; n < gridCount; ++n) {
        const auto [l, g] = gridOf[n];
        const PyramidLevel& level = m.levels[l];
        gridStart[n] = at;
        recordsAt[n] = at + prefix[n].size() + topology[n].size();
        at = recordsAt[n] + recordBytes[n];
        patchStreamPositions(prefix[n], positionsAt[n], *level.skeleton[g], level.encoding[g].half,
                             std::int64_t(gridStart[n] + positionsAt[n] + 24), std::int64_t(recordsAt[n]),
                             std::int64_t(at));
    }
    const auto laidOut = std::chrono::steady_clock::now();
    traceSpanSince("sort and lay out the leaves", start);

    // A name of this process's own: two runs writing the same output never
    // share a temporary file.
    static std::atomic<unsigned> counter{0};
    const std::string tmp = path + ".partial-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
    const std::string cannotWrite = path + ": cannot write the OpenVDB file " + tmp;
    // What goes where: the header, each grid's prefix and topology from
    // memory, its leaf records from the scratch file.
    struct MemoryPart {
        std::uint64_t at;
        std::span<const std::uint8_t> bytes;
    };
    std::vector<MemoryPart> memoryParts{{0, header}};
    std::vector<RecordPiece> pieces;
    for (std::size_t n = 0; n < gridCount; ++n) {
        memoryParts.push_back({gridStart[n], prefix[n]});
        memoryParts.push_back({gridStart[n] + prefix[n].size(), topology[n]});
        addRecordPieces(m.levels[gridOf[n].first].leaves, gridOf[n].second, recordsAt[n], pieces);
    }
    const std::uint64_t fileBytes = at;
    ChunkedOutput output(tmp, cannotWrite, m.options.outputChunkBytes);
    try {
        const auto recordsStart = std::chrono::steady_clock::now();
        output.write(fileBytes, [&](std::uint64_t chunkAt, std::span<std::uint8_t> out) {
            const std::uint64_t chunkEnd = chunkAt + out.size();
            for (const MemoryPart& part : memoryParts) {
                const std::uint64_t lo = std::max(part.at, chunkAt), hi = std::min(part.at + part.bytes.size(), chunkEnd);
                if (lo < hi) std::memcpy(out.data() + (lo - chunkAt), part.bytes.data() + (lo - part.at), hi - lo);
            }
            fillFromRecords(pieces, *m.spill, chunkAt, out);
        });
        traceSpanSince("write the file in chunks", recordsStart);
        Fd fd(output.release());
        // The scratch file is let go while the disk takes the output: freeing
        // its cached pages (as many as the output's) took 0.7 s after an
        // 8 GB write, on a core that the fsync leaves idle.
        std::jthread dropSpill([&m] { m.spill.reset(); });
        // Data on disk before the name: a crash never leaves a complete-looking file.
        const auto syncStart = std::chrono::steady_clock::now();
        if (::fsync(fd.get()) != 0) throw Error(path + ": cannot make the OpenVDB file durable: " + errnoText(errno));
        traceSpanSince("fsync", syncStart);
        if (::close(fd.release()) != 0) throw Error(path + ": cannot close the OpenVDB file: " + errnoText(errno));
        std::error_code ec;
        std::filesystem::rename(tmp, path, ec);
        if (ec) throw Error(path + ": cannot rename the finished file into place: " + ec.message());
    } catch (...) {
        std::remove(tmp.c_str());
        throw;
    }
    // The rename itself is durable only once the directory is synced.
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    const std::string dir = parent.empty() ? "." : parent.string();
    if (Fd dirFd(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC)); dirFd.get() >= 0) fsyncDir(dirFd.get(), dir);
    if (m.options.timings) {
        m.options.timings->encodeSeconds += m.encodeSeconds;
        m.options.timings->topologySeconds += std::chrono::duration<double>(laidOut - start).count() - pyramidSeconds;
        m.options.timings->writeSeconds += secondsSince(laidOut);
    }
}

void writeVdb(const std::string& path, const BrickVolume& volume, const VolumeMetadata& metadata,
              const VdbWriteOptions& options) {
    VdbWriteOptions withAlbedo = options;
    withAlbedo.albedo = options.albedo || (!volume.bricks.empty() && !volume.bricks.front().albedo.empty());
    VdbAssembler assembler(path, volume.grid, volume.reduce, withAlbedo);
    assembler.add(volume.bricks);
    assembler.write(metadata);
}

} // namespace yv

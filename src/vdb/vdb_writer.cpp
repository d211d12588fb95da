#include "vdb/vdb_writer.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/text.h"
#include "core/trace.h"
#include "vdb/chunked_output.h"
#include "vdb/coarse_levels.h"
#include "vdb/file_metadata.h"
#include "vdb/grid_checksums.h"
#include "vdb/grid_layout.h"
#include "vdb/leaf_batches.h"
#include "vdb/leaf_stream.h"
#include "vdb/lod_pyramid.h"
#include "vdb/octant_memory.h"
#include "vdb/openvdb_encoding.h"
#include "vdb/spill_file.h"
#include "vdb/tree_order.h"

#include <openvdb/openvdb.h>
#include <tbb/parallel_for.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <thread>

namespace yv {
namespace {

/// Level 0's octants stay in memory when each takes at most this many bytes:
/// the preview's 40 (52 with albedo), 3.19 M bricks and 180 MB with their
/// places at 8192 (vdb/octant_memory.h). The full pyramid's, up to 2 KB a
/// brick and gigabytes at 8192, go to the scratch file.
constexpr std::size_t kOctantsInMemoryAtMost = 64;

double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

/// The file's layout: its header, then per grid (level by level: density,
/// orientation and albedo) its prefix (its descriptor, then the grid's
/// data from gridPos: with streamed leaves, zeros between the two put the
/// records on a whole block), topology and leaf records.
struct FileLayout {
    openvdb::MetaMap fileMeta; ///< with the grids' checksums as zeros, until they are known
    std::vector<std::string> gridNames;
    ByteVector header;
    std::vector<std::pair<std::size_t, int>> gridOf; ///< (level, grid) of each grid in the file
    std::vector<ByteVector> prefix;
    std::vector<std::size_t> descriptorBytes; ///< of each prefix: the descriptor, up to gridPos
    std::vector<TopologyBytes> topology;
    std::vector<std::uint64_t> gridStart, gridPos, recordsAt, recordBytes;
    std::uint64_t fileBytes = 0;
    ByteVector zeros; ///< as many as the most any grid has before its data
};

/// Where a streamed file's bytes were written before the holes were cut
/// out (vdb/leaf_stream.h): bytes [begin, end) of the finished file lie
/// `shift` bytes further on until then.
struct FileSegment {
    std::uint64_t begin, end, shift;
};

} // namespace

struct VdbAssembler::Impl {
    std::string path;
    VoxelGrid grid;
    Reduce reduce = Reduce::Mean;
    VdbWriteOptions options;
    std::vector<PyramidLevel> levels; ///< level 0, then the pyramid's, lodFirstLevel..lodLevels
    std::unique_ptr<SpillFile> spill;
    OctantOutput octantOutput; ///< what each level-0 brick gives the first coarse level
    /// The output, made early where the leaves stream (else by writeFile).
    std::unique_ptr<PendingFile> file;
    std::unique_ptr<ChunkedOutput> output;
    std::optional<StreamLanes> lanes;
    std::unique_ptr<LeafStream> stream; ///< level 0's leaves, while bricks are added
    std::size_t bricksAdded = 0;

    mutable std::mutex mutex;
    std::vector<OctantRecord> octants; ///< where each level-0 brick's octant lies
    OctantMemory octantMemory;         ///< their bytes, when kept in memory
    std::vector<std::string> sources;
    double encodeSeconds = 0.0;
    bool written = false;

    void sortLeaves();
    double buildPyramid();
    /// With `streamedGrids`, the first as many grids' records start on a
    /// multiple of `block`.
    FileLayout layOut(const VolumeMetadata& metadata, int streamedGrids = 0, std::uint64_t block = 0);
    void openOutput();
    /// Where each part of a streamed file was written (empty where the lanes
    /// cannot hold `layout`: the file is then written whole).
    std::vector<FileSegment> streamedSegments(const FileLayout& layout) const;
    /// `segments` (streamedSegments) where `streamed` records are kept.
    void writeFile(FileLayout& layout, const LeafStream::Result* streamed = nullptr,
                   const std::vector<FileSegment>& segments = {});
};

VdbAssembler::VdbAssembler(std::string path, const VoxelGrid& grid, Reduce reduce, const VdbWriteOptions& options)
    : impl_(std::make_unique<Impl>()) {
    openvdb::initialize();
    Impl& m = *impl_;
    m.path = std::move(path);
    m.grid = grid;
    m.reduce = reduce;
    m.options = options;
    const int last = checkedLodLevels(options.lodLevels, grid), first = options.lodFirstLevel;
    YV_CHECK(first >= 1 && first <= 3 && (last == 0 || first <= last));
    m.levels.resize(last == 0 ? 1 : std::size_t(last - first) + 2);
    for (std::size_t l = 1; l < m.levels.size(); ++l) m.levels[l].number = first + int(l) - 1;
    if (last > 0) {
        m.octantOutput.skip = first;
        m.octantOutput.inMemory = octantBytesAtMost(first, options.albedo) <= kOctantsInMemoryAtMost;
    }
    for (PyramidLevel& level : m.levels) level.gridCount = options.albedo ? 3 : 2;
    const bool half = options.precision == VdbPrecision::Half;
    const std::uint32_t flags = archiveFlags(options.compression);
    for (PyramidLevel& level : m.levels) {
        // Level L's voxel (i, j, k) covers level 0's voxels 2^L (i, j, k) to 2^L (i + 1, j + 1, k + 1) - 1.
        const double h = grid.voxelSize * double(1u << level.number);
        level.transform = openvdb::math::Transform::createLinearTransform(h);
        const glm::dvec3 c = grid.origin + 0.5 * h;
        level.transform->postTranslate(openvdb::Vec3d(c.x, c.y, c.z));
        for (int g = 0; g < level.gridCount; ++g) {
            const auto kind = GridKind(g);
            level.skeleton[g] = makeSkeletonGrid(kind, level.transform, half, level.number);
            level.encoding[g] = {kind, gridCompression(flags, *level.skeleton[g]), flags, half};
            level.encoders[g] = std::make_unique<LeafEncoder>(level.encoding[g]);
        }
    }
    const std::filesystem::path dir = std::filesystem::path(m.path).parent_path();
    m.spill = std::make_unique<SpillFile>(dir.string(), "the OpenVDB file " + m.path + " (its leaves, before they are put in order)",
                                          options.scratchMemoryBytes);
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
    EncodedBatch batch = encodeBatch(m.levels[0], *m.spill, bricks, m.octantOutput);
    const double seconds = secondsSince(start);
    std::lock_guard lock(m.mutex);
    YV_CHECK(!m.written);
    const auto tag = static_cast<std::uint32_t>(m.sources.size());
    m.sources.push_back(source);
    if (m.octantOutput.inMemory) m.octantMemory.keep(batch.octants, batch.octantBytes);
    m.octants.insert(m.octants.end(), batch.octants.begin(), batch.octants.end());
    m.bricksAdded += batch.records.size();
    if (m.stream) {
        // The leaves go to the stream, the rest of the batch (bounds, counts) to the level.
        for (LeafRecord& r : batch.records) r.source = tag;
        m.stream->add(std::move(batch.records));
        batch.records.clear();
    }
    addBatch(m.levels[0], std::move(batch), tag);
    m.encodeSeconds += seconds;
}

std::size_t VdbAssembler::brickCount() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->bricksAdded;
}

void VdbAssembler::Impl::openOutput() {
    if (file) return;
    file = std::make_unique<PendingFile>(path);
    output = std::make_unique<ChunkedOutput>(file->fd(), path + ": cannot write the OpenVDB file " + file->temporaryPath(),
                                             options.outputChunkBytes);
}

bool VdbAssembler::streamRegions(std::vector<std::uint64_t> firstOrders) {
    Impl& m = *impl_;
    std::lock_guard lock(m.mutex);
    YV_CHECK(!m.written && !m.stream && m.bricksAdded == 0);
    // One region's leaves all come at once, at the end: nothing to overlap,
    // and streaming them only costs a pass (10 ms of a 0.2 s run).
    if (firstOrders.size() < 2) return false;
    m.openOutput();
    m.lanes = planStreamLanes(m.file->fd(), m.levels[0].gridCount);
    if (!m.lanes) return false;
    m.stream = std::make_unique<LeafStream>(*m.spill, *m.output, m.levels[0].gridCount, *m.lanes, std::move(firstOrders));
    return true;
}

void VdbAssembler::regionDone(std::size_t region) {
    // No lock: the stream has its own, and is made before the first brick comes.
    if (impl_->stream) impl_->stream->regionDone(region);
}

/// Puts level 0's leaves in tree order; throws when a brick came twice.
void VdbAssembler::Impl::sortLeaves() {
    std::vector<LeafRecord>& leaves = levels[0].leaves;
    sortInTreeOrder(leaves);
    for (std::size_t i = 1; i < leaves.size(); ++i) {
        if (leaves[i].order == leaves[i - 1].order) {
            const std::string& a = sources[leaves[i - 1].source];
            const std::string& b = sources[leaves[i].source];
            const std::string from = a.empty() && b.empty() ? "" : " (from " + a + " and " + b + ")";
            throw Error(path + ": brick at voxel " + coordText(treeOrderCoord(leaves[i].order) * kBrickSize) +
                        " given twice" + from + ": cannot build one volume");
        }
    }
}

/// The pyramid, level by level from the octants each level's bricks left:
/// the first coarse level from level 0's (in memory, or in the scratch
/// file), each level above from the one below's in the scratch file. Returns
/// its seconds.
double VdbAssembler::Impl::buildPyramid() {
    const TraceSpan span("build the level-of-detail pyramid");
    const auto start = std::chrono::steady_clock::now();
    std::vector<OctantRecord> pending = std::move(octants), next;
    for (std::size_t l = 1; l < levels.size(); ++l) {
        throwIfInterrupted("while writing " + path);
        const int skip = levels[l].number - levels[l - 1].number;
        const OctantSource from{*spill, l == 1 && octantOutput.inMemory ? &octantMemory : nullptr};
        buildLevel(levels[l], skip, from, pending, *spill, l + 1 < levels.size() ? &next : nullptr);
        if (l == 1) octantMemory = OctantMemory();
        std::vector<OctantRecord>().swap(pending);
        std::swap(pending, next);
        sortInTreeOrder(levels[l].leaves);
    }
    return secondsSince(start);
}

FileLayout VdbAssembler::Impl::layOut(const VolumeMetadata& metadata, int streamedGrids, std::uint64_t block) {
    FileLayout f;
    f.fileMeta = vdbFileMetadata(metadata, grid, reduce, levels.back().number, levels.size() > 1 ? levels[1].number : 1,
                                 levels[0].gridCount > 2);
    f.fileMeta.insertMeta(kVoxelStatisticsName,
                          openvdb::StringMetadata(statisticsRecord(levels[0].statistics, levels[0].leaves.size())));
    // Zoom regions on the density grid, not the file: a summary lists the
    // file's items, and a large run has thousands of regions.
    if (!metadata.regions.empty())
        levels[0].skeleton[0]->insertMeta(kRegionsMetadataName, openvdb::StringMetadata(encodeRegions(metadata.regions)));

    for (std::size_t l = 0; l < levels.size(); ++l)
        for (int g = 0; g < levels[l].gridCount; ++g) {
            f.gridOf.emplace_back(l, g);
            f.gridNames.push_back(levels[l].skeleton[g]->getName());
        }
    const std::size_t gridCount = f.gridOf.size();
    // The checksums' text has the same length whatever they are: the header's size is known now.
    f.fileMeta.insertMeta(kGridChecksumsName,
                          openvdb::StringMetadata(checksumText(f.gridNames, std::vector<std::uint64_t>(gridCount, 0))));
    f.header = fileHeaderBytes(f.fileMeta, std::int32_t(gridCount));
    f.prefix.resize(gridCount);
    f.descriptorBytes.resize(gridCount);
    f.topology.resize(gridCount);
    f.gridStart.resize(gridCount), f.gridPos.resize(gridCount), f.recordsAt.resize(gridCount);
    f.recordBytes.resize(gridCount);
    std::vector<std::size_t> positionsAt(gridCount);
    std::vector<GridStatistics> levelStats(levels.size());
    for (std::size_t l = 0; l < levels.size(); ++l) {
        const PyramidLevel& level = levels[l];
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
            if (f.gridOf[n].first == l) f.recordBytes[n] = bytes[f.gridOf[n].second];
    }
    // Each grid's prefix and topology, side by side: neither depends on where the grid lands.
    tbb::parallel_for(std::size_t(0), gridCount, [&](std::size_t n) {
        const auto [l, g] = f.gridOf[n];
        const PyramidLevel& level = levels[l];
        std::vector<LeafLoadInfo> load(level.leaves.size());
        for (std::size_t i = 0; i < level.leaves.size(); ++i) load[i] = level.leaves[i].load[g];
        f.prefix[n] = gridPrefixBytes(*level.skeleton[g], level.encoding[g], levelStats[l], load, positionsAt[n]);
        f.topology[n] = topologyBytes(level.leaves, level.encoding[g]);
    });
    std::uint64_t at = f.header.size();
    for (std::size_t n = 0; n < gridCount; ++n) {
        const auto [l, g] = f.gridOf[n];
        const PyramidLevel& level = levels[l];
        f.gridStart[n] = at;
        f.descriptorBytes[n] = positionsAt[n] + 24; // the positions end the descriptor
        const std::uint64_t dataBytes = f.prefix[n].size() - f.descriptorBytes[n] + f.topology[n].size();
        f.gridPos[n] = at + f.descriptorBytes[n];
        if (int(n) < streamedGrids) {
            const std::uint64_t slack = (block - (f.gridPos[n] + dataBytes) % block) % block;
            f.gridPos[n] += slack;
            if (f.zeros.size() < slack) f.zeros.resize(slack, 0);
        }
        f.recordsAt[n] = f.gridPos[n] + dataBytes;
        at = f.recordsAt[n] + f.recordBytes[n];
        patchStreamPositions(f.prefix[n], positionsAt[n], *level.skeleton[g], level.encoding[g].half,
                             std::int64_t(f.gridPos[n]), std::int64_t(f.recordsAt[n]), std::int64_t(at));
    }
    f.fileBytes = at;
    return f;
}

std::vector<FileSegment> VdbAssembler::Impl::streamedSegments(const FileLayout& f) const {
    // Segment n (one per streamed grid) starts at the block before its
    // descriptor and lies where the grid's records put it: its lane less
    // their place in the file. Before the first, the header, unmoved.
    const std::uint64_t block = lanes->block;
    std::vector<FileSegment> segments{{0, 0, 0}};
    for (std::size_t n = 0; n < lanes->laneAt.size(); ++n) {
        const std::uint64_t begin = f.gridStart[n] / block * block;
        if (f.recordsAt[n] > lanes->laneAt[n]) return {}; // the grid before ran into the lane
        const std::uint64_t shift = lanes->laneAt[n] - f.recordsAt[n];
        if (shift < segments.back().shift) return {};
        segments.back().end = begin;
        segments.push_back({begin, f.fileBytes, shift});
    }
    if (f.fileBytes + segments.back().shift > lanes->fileBytesAtMost) return {};
    return segments;
}

/// Writes the laid-out file in chunks, in parallel: the header, each grid's
/// prefix and topology from memory, its leaf records from the scratch file,
/// each grid hashed as its chunks are filled (vdb/grid_checksums.h); then the
/// header again with the checksums, and publishes it (core/atomic_file.h).
/// With `streamed` records, only what the stream did not write is written,
/// each part where its segment puts it, and the holes are then cut out.
void VdbAssembler::Impl::writeFile(FileLayout& f, const LeafStream::Result* streamed,
                                   const std::vector<FileSegment>& segments) {
    openOutput();
    struct MemoryPart {
        std::uint64_t at;
        std::span<const std::uint8_t> bytes;
    };
    std::vector<MemoryPart> memoryParts{{0, f.header}};
    std::vector<RecordPiece> pieces;
    for (std::size_t n = 0; n < f.gridOf.size(); ++n) {
        const std::span<const std::uint8_t> prefix(f.prefix[n]);
        const std::uint64_t descriptorEnd = f.gridStart[n] + f.descriptorBytes[n];
        memoryParts.push_back({f.gridStart[n], prefix.first(f.descriptorBytes[n])});
        memoryParts.push_back({descriptorEnd, std::span(f.zeros).first(f.gridPos[n] - descriptorEnd)});
        memoryParts.push_back({f.gridPos[n], prefix.subspan(f.descriptorBytes[n])});
        memoryParts.push_back({f.recordsAt[n] - f.topology[n].size(), f.topology[n]});
        addRecordPieces(levels[f.gridOf[n].first].leaves, f.gridOf[n].second, f.recordsAt[n], pieces);
    }
    const auto recordsStart = std::chrono::steady_clock::now();
    std::vector<RangeChecksum> sums;
    for (std::size_t n = 0; n < f.gridOf.size(); ++n)
        sums.emplace_back(f.gridStart[n], n + 1 < f.gridOf.size() ? f.gridStart[n + 1] : f.fileBytes);
    const std::string where = "while writing " + path;
    const auto fill = [&](std::uint64_t chunkAt, std::span<std::uint8_t> out) {
        throwIfInterrupted(where); // a signal stops the write at its next chunk
        const std::uint64_t chunkEnd = chunkAt + out.size();
        for (const MemoryPart& part : memoryParts) {
            const std::uint64_t lo = std::max(part.at, chunkAt), hi = std::min(part.at + part.bytes.size(), chunkEnd);
            if (lo < hi) std::memcpy(out.data() + (lo - chunkAt), part.bytes.data() + (lo - part.at), hi - lo);
        }
        fillFromRecords(pieces, *spill, chunkAt, out);
        for (RangeChecksum& sum : sums)
            if (sum.begin() < chunkEnd && sum.end() > chunkAt) sum.add(chunkAt, out);
        signalAtTestPoint("vdb-chunk");
    };
    if (!streamed) {
        output->write(f.fileBytes, fill);
    } else {
        YV_CHECK(!segments.empty());
        // Each segment but the streamed records at its start, where the stream wrote them.
        for (std::size_t s = 0; s < segments.size(); ++s) {
            const FileSegment& seg = segments[s];
            std::uint64_t skipFrom = seg.end, skipTo = seg.end;
            if (s > 0) {
                const std::size_t n = s - 1;
                skipFrom = f.recordsAt[n];
                skipTo = std::min(skipFrom + streamed->streamedBytes[n], seg.end);
                for (std::uint64_t at = skipFrom; at < skipTo; at += kChecksumBlockBytes)
                    sums[n].setBlock(at, streamed->blockSums[n][(at - skipFrom) / kChecksumBlockBytes]);
            }
            const auto writePart = [&](std::uint64_t begin, std::uint64_t end) {
                if (begin < end)
                    output->writeRange(begin + seg.shift, end + seg.shift,
                                       [&](std::uint64_t at, std::span<std::uint8_t> out) { fill(at - seg.shift, out); });
            };
            writePart(seg.begin, skipFrom);
            writePart(skipTo, seg.end);
        }
        // From the last hole to the first, so each is still where its segment says.
        for (std::size_t s = segments.size() - 1; s > 0; --s) {
            const std::uint64_t hole = segments[s].shift - segments[s - 1].shift;
            if (hole > 0 && !collapseRange(file->fd(), segments[s].begin + segments[s - 1].shift, hole))
                throw Error(path + ": cannot cut the unused " + std::to_string(hole) + " bytes out of " +
                            file->temporaryPath() + ": " + errnoText(errno));
        }
        if (::ftruncate(file->fd(), off_t(f.fileBytes)) != 0)
            throw Error(path + ": cannot set the size of " + file->temporaryPath() + ": " + errnoText(errno));
    }
    std::vector<std::uint64_t> values;
    for (const RangeChecksum& sum : sums) values.push_back(sum.value());
    f.fileMeta.insertMeta(kGridChecksumsName, openvdb::StringMetadata(checksumText(f.gridNames, values)));
    const ByteVector header = fileHeaderBytes(f.fileMeta, std::int32_t(f.gridOf.size()));
    YV_CHECK(header.size() == f.header.size());
    output->patch(0, header);
    traceSpanSince("write the file in chunks", recordsStart);
    // The scratch space is let go while the disk takes the output: freeing
    // the cached pages of its file took 0.7 s after an 8 GB write, on a core
    // that the fsync leaves idle.
    std::jthread dropSpill([this] { spill.reset(); });
    const auto syncStart = std::chrono::steady_clock::now();
    file->sync();
    traceSpanSince("fsync", syncStart);
    signalAtTestPoint("vdb-publish");
    throwIfInterrupted(where); // the last moment the file can still not be there
    file->publish();
    signalAtTestPoint("vdb-written");
}

void VdbAssembler::write(const VolumeMetadata& metadata) {
    Impl& m = *impl_;
    const auto start = std::chrono::steady_clock::now();
    std::lock_guard lock(m.mutex);
    YV_CHECK(!m.written);
    m.written = true;
    signalAtTestPoint("vdb-start");
    throwIfInterrupted("while writing " + m.path);
    std::optional<LeafStream::Result> streamed;
    std::optional<double> pyramidSeconds;
    std::optional<FileLayout> layout;
    std::vector<FileSegment> segments;
    if (m.stream) {
        // Made while the stream takes and writes its last leaves: the pyramid
        // (from the regions' octants, not level 0's leaves), then the layout.
        pyramidSeconds = m.buildPyramid();
        if (std::optional<std::vector<LeafRecord>> leaves = m.stream->finalLeaves()) {
            m.levels[0].leaves = std::move(*leaves);
            layout = m.layOut(metadata, m.levels[0].gridCount, m.lanes->block);
            segments = m.streamedSegments(*layout);
        }
        streamed = m.stream->finish();
        m.stream.reset();
        if (streamed->intact && layout) {
            streamed->leaves = {}; // the same as level 0's
        } else {
            m.levels[0].leaves = std::move(streamed->leaves);
            streamed.reset(); // out of order: sorted, and written whole
            layout.reset();
        }
    }
    if (!streamed) m.sortLeaves();
    traceSpanSince("sort the leaves", start);
    if (!pyramidSeconds) pyramidSeconds = m.buildPyramid();
    m.encodeSeconds += *pyramidSeconds;
    if (!layout) layout = m.layOut(metadata);
    if (streamed && segments.empty()) {
        streamed.reset(); // the lanes cannot hold it: written whole, as OpenVDB lays it out
        layout = m.layOut(metadata);
    }
    if (m.file && !streamed && ::ftruncate(m.file->fd(), 0) != 0) // what a stream left there
        throw Error(m.path + ": cannot empty " + m.file->temporaryPath() + ": " + errnoText(errno));
    const auto laidOut = std::chrono::steady_clock::now();
    traceSpanSince("sort and lay out the leaves", start);
    m.writeFile(*layout, streamed ? &*streamed : nullptr, segments);
    if (m.options.timings) {
        m.options.timings->encodeSeconds += m.encodeSeconds;
        m.options.timings->topologySeconds += std::chrono::duration<double>(laidOut - start).count() - *pyramidSeconds;
        m.options.timings->writeSeconds += secondsSince(laidOut);
        if (streamed) {
            for (int g = 0; g < m.levels[0].gridCount; ++g) m.options.timings->streamedBytes += streamed->streamedBytes[g];
            m.options.timings->streamedBeforeEndBytes += streamed->bytesBeforeLastRegion;
            m.options.timings->streamSeconds += streamed->seconds;
        }
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

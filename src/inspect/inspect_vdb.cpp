#include "inspect/inspect_vdb.h"

#include "core/error.h"
#include "inspect/report_text.h"
#include "inspect/volume_source.h"
#include "vdb/file_metadata.h"
#include "vdb/vdb_index.h"

#include <openvdb/openvdb.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_reduce.h>

#include <bit>
#include <climits>
#include <cstring>
#include <filesystem>
#include <optional>

namespace yv {
namespace {

template <typename GridT> GridSummary summarize(const GridT& grid, const std::string& compression) {
    GridSummary g;
    g.name = grid.getName();
    g.type = grid.type();
    g.activeVoxels = grid.activeVoxelCount();
    g.leaves = grid.tree().leafCount();
    const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
    g.boundsMin = {box.min().x(), box.min().y(), box.min().z()};
    g.boundsMax = {box.max().x(), box.max().y(), box.max().z()};
    g.halfFloat = grid.saveFloatAsHalf();
    g.compression = compression;
    return g;
}

std::string compressionOf(const openvdb::GridBase& grid) {
    if (auto m = grid.getMetadata<openvdb::StringMetadata>(openvdb::GridBase::META_FILE_COMPRESSION)) return m->value();
    return "";
}

GridSummary summarizeStored(const VdbGridInfo& g, std::uint64_t leaves, std::uint64_t activeVoxels) {
    GridSummary out;
    out.name = g.name;
    out.type = g.type;
    out.activeVoxels = activeVoxels;
    out.leaves = leaves;
    out.boundsMin = glm::ivec3(INT_MAX);
    out.boundsMax = glm::ivec3(INT_MIN);
    const StoredMetadata* lo = g.find(openvdb::GridBase::META_FILE_BBOX_MIN);
    const StoredMetadata* hi = g.find(openvdb::GridBase::META_FILE_BBOX_MAX);
    if (activeVoxels > 0 && lo && hi && lo->value.size() == 12 && hi->value.size() == 12) {
        std::memcpy(&out.boundsMin, lo->value.data(), 12);
        std::memcpy(&out.boundsMax, hi->value.data(), 12);
    }
    out.halfFloat = g.half;
    if (const StoredMetadata* c = g.find(openvdb::GridBase::META_FILE_COMPRESSION); c && c->type == "string")
        out.compression.assign(c->value.begin(), c->value.end());
    return out;
}

/// The statistics a yarnvox .vdb records (kVoxelStatisticsName), when it
/// has the item; throws yv::Error naming `path` when the item is malformed.
std::optional<RecordedStatistics> recordedStatistics(const std::string& path, const std::string* text) {
    if (!text) return std::nullopt;
    std::string why;
    std::optional<RecordedStatistics> r = parseStatisticsRecord(*text, why);
    if (!r) throw Error(path + ": file metadata " + kVoxelStatisticsName + " is damaged: " + why);
    return r;
}

/// Counted statistics against the file's record: any difference means the
/// file changed after it was written (or its writer erred).
void checkAgainstRecord(const std::string& path, const VoxelStatistics& counted, std::uint64_t leaves,
                        const RecordedStatistics& recorded) {
    std::string what;
    if (counted.activeVoxels != recorded.voxels.activeVoxels)
        what = std::to_string(counted.activeVoxels) + " active voxels, the record " +
               std::to_string(recorded.voxels.activeVoxels);
    else if (leaves != recorded.leaves)
        what = std::to_string(leaves) + " leaves, the record " + std::to_string(recorded.leaves);
    else if (!(counted == recorded.voxels))
        appendf(what, "density sum %.17g, the record %.17g (or the histogram or axes differ)", counted.densitySum(),
                recorded.voxels.densitySum());
    if (!what.empty())
        throw Error(path + ": the voxels differ from the statistics recorded when the file was written (" + what +
                    "): the file changed after it was written");
}

/// inspectVdb for a file in the subset yarnvox writes: headers from its
/// index, the voxels read range by range in parallel and dropped, so memory
/// stays at the leaf table whatever the volume.
VdbSummary inspectOwnVdb(const VdbIndex& index, VoxelCount count) {
    const std::string& path = index.path();
    VdbSummary s;
    s.path = path;
    s.fileBytes = index.file().size();
    std::optional<std::string> recordText;
    s.libraryVersion = index.libraryVersion();
    const std::string* record = nullptr;
    for (const StoredMetadata& m : index.fileMetadata()) {
        if (m.name == kVoxelStatisticsName && m.type == "string") {
            record = &recordText.emplace(m.value.begin(), m.value.end());
            continue; // summarised below, not printed as a metadata item
        }
        s.fileMetadata.emplace_back(m.name, m.text());
        if (m.name == "stage_seconds" && m.type == "string")
            s.stageSeconds = parseStageSeconds(std::string(m.value.begin(), m.value.end()), path + ": metadata stage_seconds");
    }
    const VdbGridInfo* density = index.grid("density");
    if (!density || density->vector) throw Error(path + ": has no float grid named 'density'");
    const VdbGridInfo* orientation = index.grid("orientation");
    s.regions = [&] {
        const StoredMetadata* r = density->find(kRegionsMetadataName);
        if (!r || r->type != "string") return std::vector<RecordedRegion>{};
        return decodeRegions(std::string(r->value.begin(), r->value.end()),
                             path + ": density grid metadata " + kRegionsMetadataName);
    }();
    s.voxelSize = density->voxelSize;
    const std::optional<RecordedStatistics> recorded = recordedStatistics(path, record);
    std::uint64_t leaves = 0;
    if (recorded && count == VoxelCount::RecordedWhereThere) {
        // Nothing past the header is read: a 16384 volume (28 GB) is summarised at once.
        s.hasOrientation = orientation && orientation->vector;
        s.voxels = recorded->voxels;
        s.statisticsRecorded = true;
        leaves = recorded->leaves;
    } else {
        const std::unique_ptr<VolumeSource> source = openVdbSource(path);
        s.hasOrientation = source->hasOrientation();
        tbb::enumerable_thread_specific<VoxelStatistics> statistics;
        source->forEachBrickConcurrently(glm::ivec3(INT_MIN), glm::ivec3(INT_MAX), [&](const SourceBrick& b) {
            statistics.local().addBrick(b.density, b.orientation, b.active);
        });
        for (const VoxelStatistics& part : statistics) s.voxels += part;
        leaves = source->occupiedBricks().size();
        if (recorded) checkAgainstRecord(path, s.voxels, leaves, *recorded);
        s.statisticsChecked = bool(recorded);
    }
    s.grids.push_back(summarizeStored(*density, leaves, s.voxels.activeVoxels));
    if (s.hasOrientation) s.grids.push_back(summarizeStored(*orientation, leaves, s.voxels.activeVoxels));
    return s;
}

} // namespace

std::string vdbHasNoRegions(const std::string& path) {
    return path + ": the .vdb records no zoom regions (yarnvox voxelize and merge record them in the density grid's "
                  "yarnvox_regions metadata; otherwise give the run's work directory)";
}

std::vector<RecordedRegion> recordedRegionsOf(const openvdb::GridBase& density, const std::string& path) {
    const auto text = density.getMetadata<openvdb::StringMetadata>(kRegionsMetadataName);
    if (!text) return {};
    return decodeRegions(text->value(), path + ": density grid metadata " + kRegionsMetadataName);
}

std::vector<RecordedRegion> readVdbRegions(const std::string& path) {
    openvdb::initialize();
    openvdb::io::File file(path);
    openvdb::GridBase::Ptr density;
    try {
        file.open(/*delayLoad=*/true);
        if (file.hasGrid("density")) density = file.readGridMetadata("density");
    } catch (const openvdb::Exception& e) {
        throw Error(path + ": not an OpenVDB file OpenVDB can read (" + e.what() + ")");
    }
    file.close();
    if (!density) throw Error(path + ": has no float grid named 'density'");
    return recordedRegionsOf(*density, path);
}

VdbSummary inspectVdb(const std::string& path, VoxelCount count) {
    if (const VdbIndex index(path); index.inSubset()) return inspectOwnVdb(index, count);
    openvdb::initialize();
    VdbSummary s;
    s.path = path;
    std::error_code ec;
    s.fileBytes = std::filesystem::file_size(path, ec);
    if (ec) throw Error(path + ": cannot read: " + ec.message());
    openvdb::io::File file(path);
    try {
        file.open(/*delayLoad=*/true); // topology: the counts and bounds need no values
    } catch (const openvdb::Exception& e) {
        throw Error(path + ": not an OpenVDB file OpenVDB can read (" + e.what() + ")");
    }
    s.libraryVersion = file.version();
    const openvdb::MetaMap::Ptr fileMeta = file.getMetadata(); // a copy: iterate one map
    for (auto it = fileMeta->beginMeta(); it != fileMeta->endMeta(); ++it)
        if (it->first != kVoxelStatisticsName) s.fileMetadata.emplace_back(it->first, it->second->str());
    const auto record = fileMeta->getMetadata<openvdb::StringMetadata>(kVoxelStatisticsName);
    const std::optional<RecordedStatistics> recorded = recordedStatistics(path, record ? &record->value() : nullptr);
    if (const auto stages = fileMeta->getMetadata<openvdb::StringMetadata>("stage_seconds"))
        s.stageSeconds = parseStageSeconds(stages->value(), path + ": metadata stage_seconds");

    auto density = openvdb::gridPtrCast<openvdb::FloatGrid>(file.hasGrid("density") ? file.readGrid("density") : nullptr);
    if (!density) {
        file.close();
        throw Error(path + ": has no float grid named 'density'");
    }
    openvdb::Vec3SGrid::Ptr orientation;
    if (file.hasGrid("orientation")) orientation = openvdb::gridPtrCast<openvdb::Vec3SGrid>(file.readGrid("orientation"));
    file.close();
    s.regions = recordedRegionsOf(*density, path);
    s.voxelSize = density->voxelSize()[0];
    s.grids.push_back(summarize(*density, compressionOf(*density)));
    if (orientation) s.grids.push_back(summarize(*orientation, compressionOf(*orientation)));
    s.hasOrientation = bool(orientation);

    density.reset();
    orientation.reset();
    // Voxel statistics leaf by leaf, each leaf freed once counted.
    tbb::enumerable_thread_specific<VoxelStatistics> statistics;
    openVdbSourceThroughOpenVdb(path)->forEachBrickConcurrently(
        glm::ivec3(INT_MIN), glm::ivec3(INT_MAX),
        [&](const SourceBrick& b) { statistics.local().addBrick(b.density, b.orientation, b.active); });
    for (const VoxelStatistics& part : statistics) s.voxels += part;
    // Outside the subset (another compression, say) the topology is read anyway: count, and check the record.
    if (recorded) checkAgainstRecord(path, s.voxels, s.grids[0].leaves, *recorded);
    s.statisticsChecked = bool(recorded);
    return s;
}

} // namespace yv

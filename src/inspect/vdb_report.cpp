#include "inspect/vdb_report.h"

#include "core/text.h"
#include "inspect/inspect_vdb.h"
#include "inspect/report_text.h"

#include <algorithm>

namespace yv {
namespace {

/// Where the statistics came from, as --json says it.
const char* statisticsSource(const VdbSummary& s) {
    return s.statisticsRecorded ? "recorded" : s.statisticsChecked ? "counted, equal to the record" : "counted";
}

const char* statisticsSourceText(const VdbSummary& s) {
    if (s.statisticsRecorded)
        return "recorded in the file when it was written (no voxel read; --verify counts every voxel and compares)";
    return s.statisticsChecked ? "counted from every voxel, equal to those recorded when the file was written"
                               : "counted from every voxel (the file records none)";
}

std::string vdbJson(const VdbSummary& s) {
    const double h3 = s.voxelSize * s.voxelSize * s.voxelSize;
    JsonObject meta;
    for (const auto& [k, v] : s.fileMetadata) meta.set(k, v);
    std::vector<JsonObject> grids;
    for (const GridSummary& g : s.grids)
        grids.push_back(JsonObject()
                            .set("name", g.name)
                            .set("type", g.type)
                            .set("active_voxels", g.activeVoxels)
                            .set("leaves", g.leaves)
                            .set("bounds_min", coordText(g.boundsMin))
                            .set("bounds_max", coordText(g.boundsMax))
                            .set("half_float", g.halfFloat)
                            .set("compression", g.compression));
    std::vector<JsonObject> rows;
    for (const RecordedRegion& r : s.regions)
        rows.push_back(JsonObject()
                           .set("id", r.id)
                           .set("min", coordText(r.min))
                           .set("max", coordText(r.max))
                           .set("active_voxels", r.activeVoxels));
    // The zoom regions the file records, as a work directory's table has them (boxes and heat).
    return JsonObject()
               .set("path", s.path)
               .set("kind", "vdb")
               .set("file_bytes", s.fileBytes)
               .set("openvdb_version", s.libraryVersion)
               .set("voxel_size", s.voxelSize)
               .set("metadata", meta)
               .set("grids", grids)
               .set("bytes_per_active_voxel", s.voxels.activeVoxels ? double(s.fileBytes) / double(s.voxels.activeVoxels) : 0.0)
               .set("voxels", statisticsJson(s.voxels, h3))
               .set("statistics", statisticsSource(s))
               .set("stages", stageReportObject(s.stageSeconds))
               .set("regions", std::uint64_t(s.regions.size()))
               .set("region_table", rows)
               .dump() +
           "\n";
}

std::string vdbText(const VdbSummary& s) {
    std::string out;
    appendf(out, "%s: OpenVDB file %s, %s, voxel size %.6g\n", s.path.c_str(), s.libraryVersion.c_str(),
            bytesText(double(s.fileBytes)).c_str(), s.voxelSize);
    for (const auto& [k, v] : s.fileMetadata) appendf(out, "  %s: %s\n", k.c_str(), v.c_str());
    for (const GridSummary& g : s.grids)
        appendf(out, "grid %s (%s%s): %llu active voxels in %llu leaves, bounds %s to %s%s%s\n", g.name.c_str(),
                g.type.c_str(), g.halfFloat ? ", stored as half" : "", static_cast<unsigned long long>(g.activeVoxels),
                static_cast<unsigned long long>(g.leaves), coordText(g.boundsMin).c_str(), coordText(g.boundsMax).c_str(),
                g.compression.empty() ? "" : ", compression ", g.compression.c_str());
    if (s.voxels.activeVoxels)
        appendf(out, "%.3g bytes on disk per active voxel\n", double(s.fileBytes) / double(s.voxels.activeVoxels));
    out += statisticsText(s.voxels, s.voxelSize * s.voxelSize * s.voxelSize, s.hasOrientation);
    appendf(out, "statistics: %s\n", statisticsSourceText(s));
    out += stageSecondsText(s.stageSeconds, kVdbStagesNotRecorded);
    if (s.regions.empty()) return out + "zoom regions: none recorded\n";
    std::uint64_t hottest = 0;
    for (const RecordedRegion& r : s.regions) hottest = std::max(hottest, r.activeVoxels);
    appendf(out, "zoom regions: %zu recorded (--region ID, --regions; --json lists them), the hottest with %llu active voxels\n",
            s.regions.size(), static_cast<unsigned long long>(hottest));
    return out;
}

} // namespace

std::string vdbReport(const std::string& path, bool json, bool countEveryVoxel) {
    const VdbSummary s = inspectVdb(path, countEveryVoxel ? VoxelCount::EveryVoxel : VoxelCount::RecordedWhereThere);
    return json ? vdbJson(s) : vdbText(s);
}

} // namespace yv

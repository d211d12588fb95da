#include "inspect/store_report.h"

#include "core/text.h"
#include "inspect/inspect_store.h"
#include "inspect/report_text.h"

#include <algorithm>
#include "core/run_metadata.h"

#include <sstream>

namespace yv {

const char* regionColumnName(RegionColumn column) {
    switch (column) {
    case RegionColumn::Id: return "id";
    case RegionColumn::Bricks: return "bricks";
    case RegionColumn::Active: return "active";
    case RegionColumn::Bytes: return "bytes";
    case RegionColumn::Ratio: return "ratio";
    case RegionColumn::Volume: return "volume";
    }
    return "id";
}

const std::vector<RegionColumn>& regionColumns() {
    static const std::vector<RegionColumn> columns = {RegionColumn::Active, RegionColumn::Bricks, RegionColumn::Bytes,
                                                      RegionColumn::Id,     RegionColumn::Ratio,  RegionColumn::Volume};
    return columns;
}

namespace {

double compressionRatio(const RegionRow& r) {
    return r.info.bytesOnDisk ? double(r.valueBytes) / double(r.info.bytesOnDisk) : 0.0;
}

double columnValue(const RegionRow& r, RegionColumn column) {
    switch (column) {
    case RegionColumn::Id: return double(r.info.id);
    case RegionColumn::Bricks: return double(r.info.brickCount);
    case RegionColumn::Active: return double(r.info.activeVoxels);
    case RegionColumn::Bytes: return double(r.info.bytesOnDisk);
    case RegionColumn::Ratio: return compressionRatio(r);
    case RegionColumn::Volume: {
        const glm::dvec3 e = glm::dvec3(r.info.max - r.info.min);
        return e.x * e.y * e.z;
    }
    }
    return 0.0;
}

double voxelVolume(const StoreSummary& s) {
    const double h = s.manifest.grid.voxelSize;
    return h * h * h;
}

std::string storeJson(const StoreSummary& s, bool verify) {
    std::vector<JsonObject> rows;
    for (const RegionRow& r : s.regions) {
        JsonObject row;
        row.set("id", r.info.id).set("min", coordText(r.info.min)).set("max", coordText(r.info.max));
        if (r.problem.empty())
            row.set("bricks", r.info.brickCount)
                .set("active_voxels", r.info.activeVoxels)
                .set("bytes_on_disk", r.info.bytesOnDisk)
                .set("compression_ratio", compressionRatio(r));
        else
            row.set("problem", r.problem);
        rows.push_back(row);
    }
    JsonObject run;
    for (const auto& [k, v] : runMetadataText(s.manifest.run)) run.set(k, v);
    JsonObject out;
    out.set("path", s.dir)
        .set("kind", "work_dir")
        .set("run", run)
        .set("grid_dims", coordText(s.manifest.grid.dims))
        .set("voxel_size", s.manifest.grid.voxelSize)
        .set("reduce", toString(s.manifest.reduce))
        .set("complete", s.manifest.completeRegions.has_value())
        .set("regions", std::uint64_t(s.regions.size()))
        .set("bricks", s.bricks)
        .set("active_voxels", s.activeVoxels)
        .set("bytes_on_disk", s.bytesOnDisk)
        .set("compression_ratio", s.bytesOnDisk ? double(s.valueBytes) / double(s.bytesOnDisk) : 0.0)
        .set("verified", s.verified)
        .set("bad_regions", s.badRegions)
        .set("stages", stageReportObject(s.manifest.stageSeconds))
        .set("region_table", rows);
    if (verify) out.set("voxels", statisticsJson(s.voxels, voxelVolume(s)));
    return out.dump() + "\n";
}

/// The region table's first `limit` rows (0: all) and what was left out.
std::string regionTable(const StoreSummary& s, std::size_t limit) {
    std::string out;
    appendf(out, "%12s  %-22s %-22s %10s %14s %12s %7s\n", "region", "min", "max", "bricks", "active voxels", "on disk",
            "ratio");
    const std::size_t shown = limit ? std::min(limit, s.regions.size()) : s.regions.size();
    for (std::size_t i = 0; i < shown; ++i) {
        const RegionRow& r = s.regions[i];
        if (!r.problem.empty()) {
            appendf(out, "%12llu  %s\n", static_cast<unsigned long long>(r.info.id), r.problem.c_str());
            continue;
        }
        appendf(out, "%12llu  %-22s %-22s %10llu %14llu %12s %7.2f\n", static_cast<unsigned long long>(r.info.id),
                coordText(r.info.min).c_str(), coordText(r.info.max).c_str(),
                static_cast<unsigned long long>(r.info.brickCount), static_cast<unsigned long long>(r.info.activeVoxels),
                bytesText(double(r.info.bytesOnDisk)).c_str(), compressionRatio(r));
    }
    if (shown < s.regions.size())
        appendf(out, "(%zu more; --limit 0 shows all, --sort COLUMN orders them)\n", s.regions.size() - shown);
    return out;
}

std::string storeText(const StoreSummary& s, bool verify, std::size_t limit) {
    const VoxelGrid& grid = s.manifest.grid;
    std::string out;
    appendf(out, "%s: work directory, grid %dx%dx%d, voxel %.6g, reduce %s\n", s.dir.c_str(), grid.dims.x, grid.dims.y,
            grid.dims.z, grid.voxelSize, toString(s.manifest.reduce));
    for (const auto& [k, v] : runMetadataText(s.manifest.run)) appendf(out, "  %s: %s\n", k.c_str(), v.c_str());
    appendf(out, "%zu regions (%s), %llu bricks, %llu active voxels, %s on disk for %s of values (%.2fx)\n",
            s.regions.size(), s.manifest.completeRegions ? "run complete" : "run not finished",
            static_cast<unsigned long long>(s.bricks), static_cast<unsigned long long>(s.activeVoxels),
            bytesText(double(s.bytesOnDisk)).c_str(), bytesText(double(s.valueBytes)).c_str(),
            s.bytesOnDisk ? double(s.valueBytes) / double(s.bytesOnDisk) : 0.0);
    out += stageSecondsText(s.manifest.stageSeconds, s.manifest.completeRegions
                                                         ? "made by a yarnvox that did not record them"
                                                         : "the run has not finished");
    out += regionTable(s, limit);
    if (!verify) return out;
    if (s.badRegions)
        appendf(out, "verified: %llu bad regions\n", static_cast<unsigned long long>(s.badRegions));
    else
        appendf(out, "verified: every region's checksums hold (%zu)\n", s.regions.size());
    return out + statisticsText(s.voxels, voxelVolume(s), true);
}

/// The error a damaged store ends the command with: how many, and the first.
std::string damageFailure(const StoreSummary& s) {
    if (!s.badRegions) return "";
    std::string first;
    for (const RegionRow& r : s.regions)
        if (!r.problem.empty()) {
            first = r.problem;
            break;
        }
    return s.dir + ": " + std::to_string(s.badRegions) + " of " + std::to_string(s.regions.size()) +
           " regions are damaged (first: " + first + ")";
}

} // namespace

StoreReport storeReport(const StoreReportRequest& request) {
    StoreSummary s = inspectStore(request.dir, request.verify);
    const RegionColumn column = request.sort;
    // Largest first for every column but the id.
    std::stable_sort(s.regions.begin(), s.regions.end(), [&](const RegionRow& a, const RegionRow& b) {
        return column == RegionColumn::Id ? columnValue(a, column) < columnValue(b, column)
                                          : columnValue(a, column) > columnValue(b, column);
    });
    StoreReport report;
    report.text = request.json ? storeJson(s, request.verify) : storeText(s, request.verify, request.limit);
    report.failure = damageFailure(s);
    return report;
}

} // namespace yv

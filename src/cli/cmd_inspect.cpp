// `yarnvox inspect`: numbers about what a run produced, from its work
// directory or from any .vdb with a float density grid, as text or JSON.
#include "cli/commands.h"
#include "core/error.h"
#include "core/stats.h"
#include "core/text.h"
#include "core/output_path.h"
#include "core/stage_seconds.h"
#include "inspect/html_report.h"
#include "inspect/inspect_render.h"
#include "inspect/inspect_store.h"
#include "inspect/inspect_vdb.h"
#include "inspect/run_slices.h"
#include "inspect/isosurface_mesh.h"
#include "inspect/transfer_function.h"
#include "inspect/volumetric_triangles.h"
#include "pipeline/preview_slices.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <sstream>
#include <tuple>

namespace yv {
namespace {

std::string bytesText(double b) {
    const char* units[] = {"B", "KB", "MB", "GB", "TB"};
    int u = 0;
    while (b >= 1000.0 && u < 4) b /= 1000.0, ++u;
    char buf[32];
    std::snprintf(buf, sizeof buf, u ? "%.2f %s" : "%.0f %s", b, units[u]);
    return buf;
}

JsonObject statisticsJson(const VoxelStatistics& v, double voxelVolume) {
    std::vector<JsonObject> bins;
    for (int i = 0; i < VoxelStatistics::kBins; ++i)
        bins.push_back(JsonObject().set("low", v.binLow(i)).set("high", v.binHigh(i)).set("voxels", v.histogram[std::size_t(i)]));
    JsonObject axes;
    const double n = v.unitAxes ? double(v.unitAxes) : 1.0;
    axes.set("x", v.axisComponentSum.x / n).set("y", v.axisComponentSum.y / n).set("z", v.axisComponentSum.z / n);
    return JsonObject()
        .set("active_voxels", v.activeVoxels)
        .set("density_histogram", bins)
        .set("voxels_above_one", v.aboveOne)
        .set("share_above_one", v.activeVoxels ? double(v.aboveOne) / double(v.activeVoxels) : 0.0)
        .set("density_max", v.densityMax)
        .set("fiber_volume", v.densitySum * voxelVolume)
        .set("unit_axes", v.unitAxes)
        .set("mean_abs_axis", axes);
}

void printStatistics(const VoxelStatistics& v, double voxelVolume, bool hasOrientation) {
    std::printf("density of %llu active voxels (fibre volume %.6g):\n", static_cast<unsigned long long>(v.activeVoxels),
                v.densitySum * voxelVolume);
    const std::uint64_t most = *std::max_element(v.histogram.begin(), v.histogram.end());
    for (int i = 0; i < VoxelStatistics::kBins; ++i) {
        const std::uint64_t n = v.histogram[std::size_t(i)];
        const int bar = most ? int(40.0 * double(n) / double(most) + 0.5) : 0;
        if (i == VoxelStatistics::kBins - 1)
            std::printf("  above 1    %12llu %s\n", static_cast<unsigned long long>(n), std::string(std::size_t(bar), '#').c_str());
        else
            std::printf("  %.1f - %.1f  %12llu %s\n", v.binLow(i), v.binHigh(i), static_cast<unsigned long long>(n),
                        std::string(std::size_t(bar), '#').c_str());
    }
    std::printf("  above 1 by more than 1/1024: %llu voxels (%.3g %%), largest %.6g\n",
                static_cast<unsigned long long>(v.aboveOne),
                v.activeVoxels ? 100.0 * double(v.aboveOne) / double(v.activeVoxels) : 0.0, v.densityMax);
    if (!hasOrientation) return;
    const double n = v.unitAxes ? double(v.unitAxes) : 1.0;
    std::printf("orientation: %.4g %% of the active voxels have a unit axis; mean |axis| x %.3f, y %.3f, z %.3f\n",
                v.activeVoxels ? 100.0 * double(v.unitAxes) / double(v.activeVoxels) : 0.0, v.axisComponentSum.x / n,
                v.axisComponentSum.y / n, v.axisComponentSum.z / n);
}

/// Seconds per stage, or "recorded": false where the run did not record them.
JsonObject stageSecondsJson(const StageSeconds& stages) {
    JsonObject seconds;
    for (const auto& [name, value] : stages) seconds.set(name, value);
    return JsonObject()
        .set("recorded", !stages.empty())
        .set("seconds", seconds)
        .set("total_seconds", wholeStageSum(stages));
}

void printStageSeconds(const StageSeconds& stages, const char* notRecordedWhy) {
    if (stages.empty()) {
        std::printf("time per stage: not recorded (%s)\n", notRecordedWhy);
        return;
    }
    std::string whole, parts;
    for (const auto& [name, value] : stages) {
        char text[64];
        std::snprintf(text, sizeof text, "%s %.3f s", name.c_str(), value);
        (isWholeStage(name) ? whole : parts) += std::string((isWholeStage(name) ? whole : parts).empty() ? "" : ", ") + text;
    }
    std::printf("time per stage: %s; %.3f s in all\n", whole.c_str(), wholeStageSum(stages));
    if (!parts.empty()) std::printf("  parts of them, on their own threads (they may overlap): %s\n", parts.c_str());
}

// ---- a .vdb -----------------------------------------------------------------

void reportVdb(const std::string& path, bool json) {
    const VdbSummary s = inspectVdb(path);
    const double h3 = s.voxelSize * s.voxelSize * s.voxelSize;
    if (json) {
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
        const JsonObject out = JsonObject()
                                   .set("path", s.path)
                                   .set("kind", "vdb")
                                   .set("file_bytes", s.fileBytes)
                                   .set("openvdb_version", s.libraryVersion)
                                   .set("voxel_size", s.voxelSize)
                                   .set("metadata", meta)
                                   .set("grids", grids)
                                   .set("bytes_per_active_voxel",
                                        s.voxels.activeVoxels ? double(s.fileBytes) / double(s.voxels.activeVoxels) : 0.0)
                                   .set("voxels", statisticsJson(s.voxels, h3))
                                   .set("stages", stageSecondsJson(s.stageSeconds));
        std::vector<JsonObject> rows;
        for (const RecordedRegion& r : s.regions)
            rows.push_back(JsonObject()
                               .set("id", r.id)
                               .set("min", coordText(r.min))
                               .set("max", coordText(r.max))
                               .set("active_voxels", r.activeVoxels));
        // The zoom regions the file records, as a work directory's table has them (boxes and heat).
        JsonObject withRegions = out;
        withRegions.set("regions", std::uint64_t(s.regions.size())).set("region_table", rows);
        std::printf("%s\n", withRegions.dump().c_str());
        return;
    }
    std::printf("%s: OpenVDB file %s, %s, voxel size %.6g\n", s.path.c_str(), s.libraryVersion.c_str(),
                bytesText(double(s.fileBytes)).c_str(), s.voxelSize);
    for (const auto& [k, v] : s.fileMetadata) std::printf("  %s: %s\n", k.c_str(), v.c_str());
    for (const GridSummary& g : s.grids)
        std::printf("grid %s (%s%s): %llu active voxels in %llu leaves, bounds %s to %s%s%s\n", g.name.c_str(),
                    g.type.c_str(), g.halfFloat ? ", stored as half" : "", static_cast<unsigned long long>(g.activeVoxels),
                    static_cast<unsigned long long>(g.leaves), coordText(g.boundsMin).c_str(),
                    coordText(g.boundsMax).c_str(), g.compression.empty() ? "" : ", compression ",
                    g.compression.c_str());
    if (s.voxels.activeVoxels)
        std::printf("%.3g bytes on disk per active voxel\n", double(s.fileBytes) / double(s.voxels.activeVoxels));
    printStatistics(s.voxels, h3, s.hasOrientation);
    printStageSeconds(s.stageSeconds, kVdbStagesNotRecorded);
    if (s.regions.empty()) {
        std::printf("zoom regions: none recorded\n");
        return;
    }
    std::uint64_t hottest = 0;
    for (const RecordedRegion& r : s.regions) hottest = std::max(hottest, r.activeVoxels);
    std::printf("zoom regions: %zu recorded (--region ID, --regions; --json lists them), the hottest with %llu active voxels\n",
                s.regions.size(), static_cast<unsigned long long>(hottest));
}

// ---- a work directory ---------------------------------------------------------

using RegionKey = std::function<double(const RegionRow&)>;

const std::map<std::string, RegionKey>& regionColumns() {
    static const std::map<std::string, RegionKey> columns = {
        {"id", [](const RegionRow& r) { return double(r.info.id); }},
        {"bricks", [](const RegionRow& r) { return double(r.info.brickCount); }},
        {"active", [](const RegionRow& r) { return double(r.info.activeVoxels); }},
        {"bytes", [](const RegionRow& r) { return double(r.info.bytesOnDisk); }},
        {"ratio", [](const RegionRow& r) { return r.info.bytesOnDisk ? double(r.valueBytes) / double(r.info.bytesOnDisk) : 0.0; }},
        {"volume", [](const RegionRow& r) {
             const glm::dvec3 e = glm::dvec3(r.info.max - r.info.min);
             return e.x * e.y * e.z;
         }},
    };
    return columns;
}

void reportStore(const std::string& dir, bool json, bool verify, const std::string& sortColumn, std::size_t limit) {
    StoreSummary s = inspectStore(dir, verify);
    const RegionKey& key = regionColumns().at(sortColumn);
    // Largest first for every column but the id.
    std::stable_sort(s.regions.begin(), s.regions.end(), [&](const RegionRow& a, const RegionRow& b) {
        return sortColumn == "id" ? key(a) < key(b) : key(a) > key(b);
    });
    const VoxelGrid& grid = s.manifest.grid;
    const double h3 = grid.voxelSize * grid.voxelSize * grid.voxelSize;
    const auto run = runMetadataText(s.manifest.run);
    const double ratio = s.bytesOnDisk ? double(s.valueBytes) / double(s.bytesOnDisk) : 0.0;
    if (json) {
        std::vector<JsonObject> rows;
        for (const RegionRow& r : s.regions) {
            JsonObject row;
            row.set("id", r.info.id).set("min", coordText(r.info.min)).set("max", coordText(r.info.max));
            if (r.problem.empty())
                row.set("bricks", r.info.brickCount)
                    .set("active_voxels", r.info.activeVoxels)
                    .set("bytes_on_disk", r.info.bytesOnDisk)
                    .set("compression_ratio", regionColumns().at("ratio")(r));
            else
                row.set("problem", r.problem);
            rows.push_back(row);
        }
        JsonObject runJson;
        for (const auto& [k, v] : run) runJson.set(k, v);
        JsonObject out;
        out.set("path", s.dir)
            .set("kind", "work_dir")
            .set("run", runJson)
            .set("grid_dims", coordText(grid.dims))
            .set("voxel_size", grid.voxelSize)
            .set("reduce", toString(s.manifest.reduce))
            .set("complete", s.manifest.completeRegions.has_value())
            .set("regions", std::uint64_t(s.regions.size()))
            .set("bricks", s.bricks)
            .set("active_voxels", s.activeVoxels)
            .set("bytes_on_disk", s.bytesOnDisk)
            .set("compression_ratio", ratio)
            .set("verified", s.verified)
            .set("bad_regions", s.badRegions)
            .set("stages", stageSecondsJson(s.manifest.stageSeconds))
            .set("region_table", rows);
        if (verify) out.set("voxels", statisticsJson(s.voxels, h3));
        std::printf("%s\n", out.dump().c_str());
    } else {
        std::printf("%s: work directory, grid %dx%dx%d, voxel %.6g, reduce %s\n", s.dir.c_str(), grid.dims.x,
                    grid.dims.y, grid.dims.z, grid.voxelSize, toString(s.manifest.reduce));
        for (const auto& [k, v] : run) std::printf("  %s: %s\n", k.c_str(), v.c_str());
        std::printf("%zu regions (%s), %llu bricks, %llu active voxels, %s on disk for %s of values (%.2fx)\n",
                    s.regions.size(), s.manifest.completeRegions ? "run complete" : "run not finished",
                    static_cast<unsigned long long>(s.bricks), static_cast<unsigned long long>(s.activeVoxels),
                    bytesText(double(s.bytesOnDisk)).c_str(), bytesText(double(s.valueBytes)).c_str(), ratio);
        printStageSeconds(s.manifest.stageSeconds, s.manifest.completeRegions
                                                       ? "made by a yarnvox that did not record them"
                                                       : "the run has not finished");
        std::printf("%12s  %-22s %-22s %10s %14s %12s %7s\n", "region", "min", "max", "bricks", "active voxels",
                    "on disk", "ratio");
        const std::size_t shown = limit ? std::min(limit, s.regions.size()) : s.regions.size();
        for (std::size_t i = 0; i < shown; ++i) {
            const RegionRow& r = s.regions[i];
            if (!r.problem.empty()) {
                std::printf("%12llu  %s\n", static_cast<unsigned long long>(r.info.id), r.problem.c_str());
                continue;
            }
            std::printf("%12llu  %-22s %-22s %10llu %14llu %12s %7.2f\n", static_cast<unsigned long long>(r.info.id),
                        coordText(r.info.min).c_str(), coordText(r.info.max).c_str(),
                        static_cast<unsigned long long>(r.info.brickCount),
                        static_cast<unsigned long long>(r.info.activeVoxels), bytesText(double(r.info.bytesOnDisk)).c_str(),
                        regionColumns().at("ratio")(r));
        }
        if (shown < s.regions.size())
            std::printf("(%zu more; --limit 0 shows all, --sort COLUMN orders them)\n", s.regions.size() - shown);
        if (verify) {
            std::printf("verified: %s\n", s.badRegions ? (std::to_string(s.badRegions) + " bad regions").c_str()
                                                        : ("every region's checksums hold (" +
                                                           std::to_string(s.regions.size()) + ")").c_str());
            printStatistics(s.voxels, h3, true);
        }
    }
    if (s.badRegions) {
        std::string first;
        for (const RegionRow& r : s.regions)
            if (!r.problem.empty()) {
                first = r.problem;
                break;
            }
        throw Error(s.dir + ": " + std::to_string(s.badRegions) + " of " + std::to_string(s.regions.size()) +
                    " regions are damaged (first: " + first + ")");
    }
}

// ---- renders --------------------------------------------------------------------

/// "512M", "2G", "65536": bytes, with an optional K, M or G (powers of 1024).
std::uint64_t parseBytes(const std::string& text, const char* option) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    std::string unit(end);
    double scale = 1.0;
    if (unit == "K" || unit == "k") scale = 1024.0;
    else if (unit == "M" || unit == "m") scale = 1024.0 * 1024.0;
    else if (unit == "G" || unit == "g") scale = 1024.0 * 1024.0 * 1024.0;
    else if (!unit.empty()) scale = -1.0;
    if (end == text.c_str() || scale < 0.0 || !(v > 0.0) || v * scale > 1e15)
        throw Error(std::string(option) + " '" + text + "': expected a positive size in bytes, with K, M or G");
    return std::uint64_t(v * scale);
}

/// "WxH", each from 1 to 16384.
std::pair<int, int> parseSize(const std::string& text) {
    int w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || x != 'x' || w < 1 || h < 1 || w > 16384 ||
        h > 16384)
        throw Error("--size '" + text + "': expected WIDTHxHEIGHT, each from 1 to 16384 pixels");
    return {w, h};
}

struct RenderArgs {
    std::string render, output, view = "30,20,4", size = "800x600", tf = "fibre", cut, budget = "512M", garment, light,
        mesh;
    std::int64_t region = -1;
    int slices = 0;
    double iso = 0.5;
    int meshLevel = -1;
    PreviewSliceOptions preview; ///< volumetric-triangles: how the garment is sliced
    bool noSkip = false, showSamples = false, regions = false;
    int device = -1, repeat = 1;
    double yarnRadius = 0.0;
};

/// The zoom regions' boxes, hot by their active voxels (neither the store
/// nor the .vdb keeps fragment counts), from a work directory or from what a
/// .vdb records.
std::vector<RegionHeat> regionHeat(const std::string& input) {
    std::vector<RegionHeat> out;
    if (!std::filesystem::is_directory(input)) {
        for (const RecordedRegion& r : readVdbRegions(input))
            out.push_back(RegionHeat{r.id, VoxelBox{r.min, r.max}, double(r.activeVoxels)});
        if (out.empty()) throw Error(vdbHasNoRegions(input));
        return out;
    }
    for (const RegionRow& r : inspectStore(input, false).regions)
        out.push_back(RegionHeat{r.info.id, VoxelBox{r.info.min, r.info.max}, double(r.info.activeVoxels)});
    return out;
}

/// The heat scale the outlines' colours stand for.
std::pair<double, double> heatRange(const std::vector<RegionHeat>& regions) {
    double low = regions.front().heat, high = low;
    for (const RegionHeat& h : regions) low = std::min(low, h.heat), high = std::max(high, h.heat);
    return {low, high};
}

JsonObject regionHeatJson(const std::vector<RegionHeat>& regions) {
    const auto [low, high] = heatRange(regions);
    return JsonObject()
        .set("regions", std::uint64_t(regions.size()))
        .set("measure", "active_voxels")
        .set("low", low)
        .set("high", high)
        .set("colours", "blue (low), red, yellow (high)");
}

void printRegionHeat(const std::vector<RegionHeat>& regions) {
    const auto [low, high] = heatRange(regions);
    std::printf("region outlines: %zu regions coloured by active voxels, blue %.0f, red %.0f, yellow %.0f (the legend "
                "bar at the bottom left)\n",
                regions.size(), low, 0.5 * (low + high), high);
}

void renderToPng(const std::string& input, const RenderArgs& a, bool json) {
    RenderRequest r;
    r.kind = parseRenderKind(a.render);
    r.view = parseView(a.view);
    std::tie(r.width, r.height) = parseSize(a.size);
    if (a.region >= 0) r.region = std::uint64_t(a.region);
    r.transferFunction = a.tf;
    r.skipEmpty = !a.noSkip;
    r.showSamples = a.showSamples;
    r.isoValue = a.iso;
    if (r.kind == RenderKind::Cut) {
        if (a.cut.empty()) throw Error("--render cut needs --cut x|y|z:INDEX");
        r.cut = parseCut(a.cut);
    } else if (!a.cut.empty()) {
        throw Error("--cut goes with --render cut");
    }
    const bool sliced = r.kind == RenderKind::TextureSlicing || r.kind == RenderKind::HalfAngle;
    const bool marched = r.kind == RenderKind::Raycast || r.kind == RenderKind::Mip ||
                         r.kind == RenderKind::Orientation || r.kind == RenderKind::Isosurface;
    if ((a.noSkip || a.showSamples) && !marched)
        throw Error(std::string(a.noSkip ? "--no-skip" : "--show-samples") +
                    " goes with --render raycast, mip, orientation or isosurface");
    if (a.slices > 0 && !sliced) throw Error("--slices goes with --render texture-slicing or half-angle");
    r.slicePlanes = a.slices;
    if (!a.light.empty()) {
        if (r.kind != RenderKind::HalfAngle) throw Error("--light goes with --render half-angle");
        r.light = parseLight(a.light);
    }
    r.gpuBudgetBytes = parseBytes(a.budget, "--gpu-budget");
    r.device = a.device;
    r.repeat = a.repeat;
    if (a.output.empty()) throw Error("--render needs -o FILE.png");
    if (r.kind != RenderKind::Slices && !a.garment.empty()) throw Error("--garment goes with --render slices");
    if (r.kind != RenderKind::Slices && r.kind != RenderKind::VolumetricTriangles && a.yarnRadius > 0.0)
        throw Error("--yarn-radius goes with --render slices or volumetric-triangles");
    if (a.regions && r.kind == RenderKind::VolumetricTriangles)
        throw Error("--regions goes with the renders of a volume, not volumetric-triangles");
    if (a.regions && r.kind == RenderKind::Cut) throw Error("--regions goes with the perspective renders, not a cut");
    checkOutputPath(a.output, "-o", {input});
    if (r.kind != RenderKind::Cut) loadTransferFunction(r.transferFunction); // a bad --tf fails before any work

    RenderReport rep;
    SliceInstances slices;
    std::vector<std::string> notes;
    if (r.kind == RenderKind::VolumetricTriangles) {
        // A garment is sliced as voxelize slices it; a volume's slices come
        // from the garment it was made from, framed by the volume's own box.
        PreviewSliceOptions preview = a.preview;
        preview.yarnRadius = a.yarnRadius;
        const bool garment = !std::filesystem::is_directory(input) && std::filesystem::path(input).extension() != ".vdb";
        const PreviewSlices previewSlices =
            garment ? garmentPreviewSlices(input, preview) : volumePreviewSlices(input, preview);
        VoxelBox box = sliceBox(previewSlices.plan, previewSlices.grid);
        if (!garment) {
            const std::unique_ptr<VolumeSource> source = openVolumeSource(input);
            box = r.region ? source->regionBounds(*r.region) : source->bounds();
        } else if (r.region) {
            throw Error("--region needs a work directory, not a garment");
        }
        rep = renderVolumetricTriangles(previewSlices.plan, previewSlices.grid, box, r, previewSlices.yarnDensity);
    } else {
        const std::unique_ptr<VolumeSource> source = openVolumeSource(input);
        if (a.regions) r.outlines = regionHeat(input);
        if (r.kind == RenderKind::Slices) {
            const RunSlices run = loadRunSlices(input, RunSlicesOptions{a.garment, a.yarnRadius});
            slices = sliceInstances(run.plan, run.grid);
            // A framed region shows its own slices, not the ones in front of it.
            if (r.region) {
                const VoxelBox box = source->regionBounds(*r.region);
                keepSlicesWithin(slices, glm::dvec3(box.min), glm::dvec3(box.max));
            }
            r.slices = &slices;
            notes = run.notes;
            notes.insert(notes.begin(), "slices of " + run.garmentPath);
        }
        rep = renderVolume(*source, r);
    }
    writePng(a.output, rep.image);
    if (json) {
        JsonObject out;
        out.set("path", input).set("output", a.output).set("render", a.render).set("width", rep.image.width)
            .set("height", rep.image.height);
        if (!r.outlines.empty()) out.set("region_heat", regionHeatJson(r.outlines));
        if (r.kind == RenderKind::VolumetricTriangles) {
            out.set("view", a.view)
                .set("renderer", rep.renderer)
                .set("frames", r.repeat)
                .set("frame_seconds_median", rep.frameSeconds)
                .set("frame_seconds_best", rep.bestFrameSeconds);
        } else if (r.kind == RenderKind::Slices) {
            out.set("view", a.view)
                .set("renderer", rep.renderer)
                .set("slices", rep.slices)
                .set("frames", r.repeat)
                .set("sort_seconds_median", rep.sortSeconds)
                .set("sort_seconds_best", rep.bestSortSeconds)
                .set("frame_seconds_median", rep.frameSeconds)
                .set("frame_seconds_best", rep.bestFrameSeconds)
                .set("load_seconds", rep.loadSeconds);
            std::string joined;
            for (const std::string& n : notes) joined += (joined.empty() ? "" : "; ") + n;
            out.set("notes", joined);
        } else if (r.kind != RenderKind::Cut)
            out.set("view", a.view)
                .set("renderer", rep.renderer)
                .set("skip_empty", r.skipEmpty && marched)
                .set("gpu_budget_bytes", rep.budgetBytes)
                .set("level", rep.level)
                .set("fine_bricks", rep.fineBricks)
                .set("level_bricks", rep.levelBricks)
                .set("gpu_bytes", rep.gpuBytes)
                .set("proxy_triangles", rep.proxyTriangles)
                .set("mean_samples_per_pixel", rep.meanSamples)
                .set("frames", r.repeat)
                .set("frame_seconds_median", rep.frameSeconds)
                .set("frame_seconds_best", rep.bestFrameSeconds)
                .set("load_seconds", rep.loadSeconds);
        if (rep.slices) out.set("slices", rep.slices);
        if (rep.splats) out.set("splats", rep.splats);
        std::printf("%s\n", out.dump().c_str());
        return;
    }
    if (r.kind == RenderKind::Cut) {
        std::printf("%s: cut %s, %dx%d pixels, one a voxel\n", a.output.c_str(), a.cut.c_str(), rep.image.width,
                    rep.image.height);
        return;
    }
    if (!r.outlines.empty()) printRegionHeat(r.outlines);
    if (r.kind == RenderKind::VolumetricTriangles) {
        std::printf("%s: volumetric-triangles, %dx%d, on %s; frame %.3f s%s (slices placed and drawn)\n", a.output.c_str(),
                    r.width, r.height, rep.renderer.c_str(), rep.frameSeconds, r.repeat > 1 ? " (median)" : "");
        return;
    }
    if (r.kind == RenderKind::Slices) {
        std::printf("%s: slices, %dx%d, on %s\n", a.output.c_str(), r.width, r.height, rep.renderer.c_str());
        for (const std::string& n : notes) std::printf("  %s\n", n.c_str());
        std::printf("  %llu slices; back-to-front sort %.3f s (on %s), draw %.3f s%s (uploading %.3f s)\n",
                    static_cast<unsigned long long>(rep.slices), rep.sortSeconds, "every core", rep.frameSeconds,
                    r.repeat > 1 ? " (medians)" : "", rep.loadSeconds);
        return;
    }
    std::printf("%s: %s, %dx%d, on %s\n", a.output.c_str(), a.render.c_str(), r.width, r.height, rep.renderer.c_str());
    if (rep.level > 0)
        std::printf("  the %llu occupied bricks exceed the GPU budget (%s): drawn at level %d, each voxel the mean of "
                    "%dx%dx%d voxels (%llu bricks, %s)\n",
                    static_cast<unsigned long long>(rep.fineBricks), bytesText(double(rep.budgetBytes)).c_str(), rep.level,
                    1 << rep.level, 1 << rep.level, 1 << rep.level, static_cast<unsigned long long>(rep.levelBricks),
                    bytesText(double(rep.gpuBytes)).c_str());
    else
        std::printf("  %llu bricks at full resolution, %s on the GPU\n", static_cast<unsigned long long>(rep.levelBricks),
                    bytesText(double(rep.gpuBytes)).c_str());
    if (!marched) {
        const std::string drawn = rep.splats ? std::to_string(rep.splats) + " voxels splatted (the empty ones culled on the GPU)"
                                             : std::to_string(rep.slices) + " slices";
        std::printf("  %s; frame %.3f s%s (loading %.3f s)\n", drawn.c_str(), rep.frameSeconds, r.repeat > 1 ? " (median)" : "",
                    rep.loadSeconds);
        return;
    }
    std::printf("  empty-space skipping %s%s; mean samples per pixel %.2f; frame %.3f s%s (loading %.3f s)\n",
                r.skipEmpty ? "on" : "off",
                r.skipEmpty ? (" (" + std::to_string(rep.proxyTriangles) + " proxy triangles)").c_str() : "",
                rep.meanSamples, rep.frameSeconds, r.repeat > 1 ? " (median)" : "", rep.loadSeconds);
}

/// --mesh: the isosurface at --iso as a mesh, at --mesh-level or at full
/// resolution when its estimated size is within kMeshTriangleLimit.
void meshToFile(const std::string& input, const RenderArgs& a, bool json) {
    checkMeshPath(a.mesh);
    checkOutputPath(a.mesh, "--mesh", {input});
    const std::unique_ptr<VolumeSource> source = openVolumeSource(input);
    if (source->occupiedBricks().empty()) throw Error("nothing to mesh: the volume has no active voxels");
    const VoxelBox box = a.region >= 0 ? source->regionBounds(std::uint64_t(a.region)) : source->bounds();
    const int level = std::max(a.meshLevel, 0);
    const std::uint64_t estimate = estimateMeshTriangles(*source, box, level);
    if (a.meshLevel < 0 && estimate > kMeshTriangleLimit) {
        int coarser = 1;
        while (coarser < 21 && estimateMeshTriangles(*source, box, coarser) > kMeshTriangleLimit) ++coarser;
        throw Error("--mesh " + a.mesh + ": the full-resolution isosurface would have about " +
                    std::to_string(estimate / 1000000) + " million triangles (about " +
                    bytesText(double(estimate) * 19.0) + " as PLY), above the " +
                    std::to_string(kMeshTriangleLimit / 1000000) + " million written without --mesh-level; give --mesh-level " +
                    std::to_string(coarser) + " (about " +
                    std::to_string(estimateMeshTriangles(*source, box, coarser) / 1000000) + " million) or coarser");
    }
    const IsosurfaceMesh mesh = extractIsosurface(*source, box, a.iso, level);
    writeMesh(a.mesh, mesh);
    if (json) {
        std::printf("%s\n", JsonObject()
                                .set("path", input)
                                .set("mesh", a.mesh)
                                .set("iso", a.iso)
                                .set("level", level)
                                .set("vertices", std::uint64_t(mesh.vertices.size()))
                                .set("triangles", std::uint64_t(mesh.triangles.size()))
                                .dump()
                                .c_str());
        return;
    }
    std::printf("%s: isosurface at density %g%s, %zu vertices, %zu triangles (voxel coordinates)\n", a.mesh.c_str(), a.iso,
                level ? (", level " + std::to_string(level)).c_str() : "", mesh.vertices.size(), mesh.triangles.size());
}

/// --html: the report of a work directory or .vdb, written to `dir` whole.
void writeReport(const std::string& input, const std::string& dir, std::size_t renders, const RenderArgs& a) {
    if (!a.render.empty() || !a.output.empty()) throw Error("--html writes its own renders: leave out --render and -o");
    HtmlReportOptions o;
    o.regionRenders = renders;
    o.view = parseView(a.view);
    std::tie(o.width, o.height) = parseSize(a.size);
    o.transferFunction = a.tf;
    loadTransferFunction(o.transferFunction); // a bad --tf fails before any work
    o.gpuBudgetBytes = parseBytes(a.budget, "--gpu-budget");
    o.device = a.device;
    const HtmlReportResult r = writeHtmlReport(input, dir, o);
    std::printf("%s/index.html: report with %zu pictures", dir.c_str(), r.images);
    if (r.regions) std::printf(", renders of %zu of %zu regions", r.renderedRegions, r.regions);
    std::printf("\n");
}

} // namespace

void addInspectCommand(CLI::App& app) {
    struct Args {
        std::string path, sort = "id";
        bool json = false, verify = false;
        std::size_t limit = 20;
    };
    auto args = std::make_shared<Args>();
    auto render = std::make_shared<RenderArgs>();
    auto html = std::make_shared<std::pair<std::string, std::size_t>>("", 8); // --html DIR, --html-renders N
    CLI::App* cmd = app.add_subcommand(
        "inspect", "Numbers about a voxelization: a work directory's regions, or a .vdb's grids and voxels");
    cmd->add_option("path", args->path, "A work directory (--work-dir, --keep-work-dir) or an OpenVDB file with a float 'density' grid (or, "
                    "for --render volumetric-triangles, a .bcc garment)")
        ->required()
        ->check(CLI::ExistingPath);
    cmd->add_flag("--json", args->json, "Print JSON instead of text");
    cmd->add_flag("--verify", args->verify,
                  "Work directory: read every region in full, check its checksums, and exit 1 naming the damaged ones");
    std::vector<std::string> columns;
    for (const auto& [name, _] : regionColumns()) columns.push_back(name);
    cmd->add_option("--sort", args->sort, "Work directory: order the region table by this column (largest first)")
        ->capture_default_str()
        ->check(CLI::IsMember(columns));
    cmd->add_option("--limit", args->limit, "Work directory: rows of the region table to print (0: all; JSON has all)")
        ->capture_default_str();
    cmd->add_option("--render", render->render,
                    "Draw a picture to -o instead of printing numbers: raycast (transfer function), mip (maximum "
                    "density along each ray), cut (one plane of voxels, --cut), orientation (|axis| as RGB), slices "
                    "(the run's garment as alpha-blended slices shaded by fibre orientation, sorted back to front on "
                    "every core; the garment and slice options the run recorded, or --garment), texture-slicing "
                    "(view-aligned planes blended back to front, --slices), half-angle (planes lit by a directional "
                    "light, --light, with shadows), splatting (each voxel a Gaussian splat, for comparing coarse "
                    "levels with raycast), isosurface (the surface at density --iso, shaded by the density gradient) "
                    "or volumetric-triangles (the garment's slices as blurred volumetric triangles, no voxelizing; the "
                    "path may be a .bcc garment, or a volume whose recorded garment is still there)")
        ->check(CLI::IsMember({"raycast", "mip", "cut", "orientation", "slices", "texture-slicing", "half-angle",
                               "splatting", "isosurface", "volumetric-triangles"}));
    cmd->add_option("-o,--output", render->output, "--render: the PNG to write (replaced atomically)");
    cmd->add_option("--view", render->view,
                    "--render: azimuth,elevation,distance: degrees about +z from +x, degrees above the xy plane, "
                    "bounding-sphere radii from the centre (4 fits the volume)")
        ->capture_default_str();
    cmd->add_option("--size", render->size, "--render: picture size WIDTHxHEIGHT")->capture_default_str();
    cmd->add_option("--region", render->region,
                    "--render: frame and draw only this zoom region of a work directory or of a .vdb that records its "
                    "regions (yarnvox voxelize and merge write them)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_flag("--regions", render->regions,
                  "--render (not cut): draw the zoom-region boxes of the work directory or of the .vdb over the "
                  "picture, coloured by "
                  "heat (active voxels: blue, red, yellow; legend bar at the bottom left, scale printed)");
    cmd->add_option("--garment", render->garment,
                    "--render slices: the garment (.bcc) to draw, instead of the one the run recorded (needed for a "
                    ".vdb not made by yarnvox or a garment that moved)")
        ->check(CLI::ExistingFile);
    cmd->add_option("--yarn-radius", render->yarnRadius,
                    "--render slices|volumetric-triangles: yarn radius in world units, instead of the one the run "
                    "recorded (a bare garment: the garment file's, else estimated)")
        ->check(CLI::PositiveNumber);
    std::string presets;
    for (const std::string& n : transferFunctionPresets()) presets += (presets.empty() ? "" : ", ") + n;
    cmd->add_option("--tf", render->tf,
                    "--render raycast|orientation|texture-slicing|half-angle|splatting: transfer function, a preset (" + presets +
                        ") or a colour map file (lines 'density r g b opacity', formats/transfer-function.md)")
        ->capture_default_str();
    cmd->add_option("--slices", render->slices,
                    "--render texture-slicing|half-angle: slices through the box (0: one per voxel of the drawn "
                    "level across the box's depth)")
        ->check(CLI::Range(0, 100000))
        ->capture_default_str();
    cmd->add_option("--light", render->light,
                    "--render half-angle: azimuth,elevation the light comes from, degrees as in --view (default 75,45)");
    cmd->add_flag("--no-skip", render->noSkip, "--render raycast|mip|orientation|isosurface: march every ray through the whole box (no empty-space skipping)");
    cmd->add_flag("--show-samples", render->showSamples, "--render raycast|mip|orientation|isosurface: picture the samples taken per pixel instead");
    cmd->add_option("--iso", render->iso, "--render isosurface and --mesh: the density the surface lies at")
        ->check(CLI::Range(1e-6, 1e6))
        ->capture_default_str();
    cmd->add_option("--mesh", render->mesh,
                    "Write the isosurface at --iso as a mesh (.ply binary or .obj, voxel coordinates), extracted by "
                    "OpenVDB's volumeToMesh; refused when larger than about 100 million triangles unless --mesh-level");
    cmd->add_option("--mesh-level", render->meshLevel,
                    "--mesh: extract at this level of detail (0: full resolution; L: each voxel the mean of 2^L a side)")
        ->check(CLI::Range(0, 20));
    cmd->add_option("--resolution", render->preview.resolution,
                    "--render volumetric-triangles of a garment: voxels on the longest axis of the grid it is drawn on "
                    "(sets the blur and the slice spacing; default " + std::to_string(kPreviewResolution) + ")")
        ->check(CLI::Range(8, 1 << 20));
    cmd->add_option("--slice-spacing", render->preview.spacing,
                    "--render volumetric-triangles: distance between slices along a yarn, world units (default: one "
                    "voxel, as voxelize)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--cross-section", render->preview.crossSection,
                    "--render volumetric-triangles: fibre density on each slice, fibers, disk or FILE.png; its mean "
                    "over the yarn's disk is the preview's density (default: the volume's, else fibers)");
    cmd->add_option("--slices-per-segment", render->preview.slicesPerSegment,
                    "--render volumetric-triangles: slices per curve segment, instead of --slice-spacing")
        ->check(CLI::Range(1, 100000));
    cmd->add_option("--cut", render->cut, "--render cut: the plane, x|y|z:INDEX (voxel index)");
    cmd->add_option("--gpu-budget", render->budget,
                    "--render: GPU memory for the brick atlas (K, M, G); a volume that needs more is drawn at a "
                    "coarser level")
        ->capture_default_str();
    cmd->add_option("--repeat", render->repeat, "--render: draw the frame this many times and report the median time")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    cmd->add_option("--device", render->device, "--render: EGL device index (-1: the first GPU, else llvmpipe)")
        ->capture_default_str();
    cmd->add_option("--html", html->first,
                    "Write a report to this directory, for a browser without a server: summary, density histogram, "
                    "time per stage, regions coloured by heat linked to their table rows, and renders (PNG files) of "
                    "the whole volume and the hottest regions (--view, --size, --tf, --gpu-budget apply). The "
                    "directory is replaced whole at the end; an existing one must be empty or an earlier report");
    cmd->add_option("--html-renders", html->second, "--html: render this many regions, those with the most active voxels")
        ->capture_default_str()
        ->check(CLI::Range(0, 10000));
    cmd->callback([args, render, html] {
        if (!html->first.empty()) {
            writeReport(args->path, html->first, html->second, *render);
            return;
        }
        if (render->meshLevel >= 0 && render->mesh.empty()) throw Error("--mesh-level goes with --mesh");
        if (!render->mesh.empty()) meshToFile(args->path, *render, args->json && render->render.empty());
        if (!render->render.empty()) {
            renderToPng(args->path, *render, args->json);
            return;
        }
        if (!render->mesh.empty()) return;
        if (!render->output.empty()) throw Error("-o goes with --render");
        if (std::filesystem::is_directory(args->path))
            reportStore(args->path, args->json, args->verify, args->sort, args->limit);
        else
            reportVdb(args->path, args->json);
    });
}

} // namespace yv

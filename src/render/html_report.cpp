#include "render/html_report.h"

#include "core/error.h"
#include "core/text.h"
#include "inspect/html_page.h"
#include "inspect/inspect_store.h"
#include "inspect/inspect_vdb.h"
#include "inspect/png_image.h"
#include "inspect/report_directory.h"
#include "inspect/report_text.h"
#include "render/render_volume.h"

#include <glm/common.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <future>
#include <memory>
#include <optional>
#include "core/run_metadata.h"

#include <sstream>
#include <utility>
#include <vector>

namespace yv {
namespace {

namespace fs = std::filesystem;

struct HtmlReportResult {
    std::size_t regions = 0;         ///< in the work directory, or recorded in the .vdb (0 where none)
    std::size_t renderedRegions = 0; ///< of them, with renders on the page
};

/// The report's renders of one volume, each to DIR/renders/NAME.png, all on the command's context.
struct ReportPictures {
    RenderContext& context;
    const HtmlReportRequest& request;
    fs::path dir;
    std::unique_ptr<VolumeSource> source;

    /// Draws one picture and returns its file, relative to the page.
    std::string draw(const std::string& name, RenderKind kind, std::optional<std::uint64_t> region, int w, int h) {
        RenderRequest r;
        r.kind = kind;
        r.view = request.view;
        r.width = w;
        r.height = h;
        r.region = region;
        r.transferFunction = request.transferFunction;
        r.gpuBudgetBytes = request.gpuBudgetBytes;
        const RenderReport rep = renderVolume(context, *source, r);
        const std::string file = "renders/" + name + ".png";
        writePng((dir / file).string(), rep.image);
        return file;
    }
};

std::string wholeVolumeRenders(ReportPictures& pictures) {
    const HtmlReportRequest& o = pictures.request;
    const int w = o.width / 2;
    const auto figure = [&](const char* name, RenderKind kind, const char* alt, const std::string& caption) {
        return "<figure>" + imageLink(pictures.draw(name, kind, std::nullopt, o.width, o.height), alt, w) +
               "<figcaption>" + caption + "</figcaption></figure>\n";
    };
    std::string s = "<h2 id=\"renders\">The whole volume</h2>\n<div class=\"renders\">\n";
    s += figure("volume-raycast", RenderKind::Raycast, "ray cast of the whole volume",
                "ray cast (transfer function " + htmlEscape(o.transferFunctionName) + ")");
    s += figure("volume-mip", RenderKind::Mip, "maximum intensity projection of the whole volume",
                "maximum density along each ray");
    if (pictures.source->hasOrientation())
        s += figure("volume-orientation", RenderKind::Orientation, "orientation of the whole volume",
                    "orientation, |axis| as RGB");
    return s + "</div>\n";
}

RegionRenders renderHottestRegions(ReportPictures& pictures, const std::vector<RegionRow>& regions) {
    std::vector<const RegionRow*> byHeat;
    for (const RegionRow& r : regions)
        if (r.problem.empty() && r.info.activeVoxels > 0) byHeat.push_back(&r);
    std::stable_sort(byHeat.begin(), byHeat.end(),
                     [](const RegionRow* a, const RegionRow* b) { return a->info.activeVoxels > b->info.activeVoxels; });
    RegionRenders out;
    out.hottest = byHeat.empty() ? 0 : byHeat.front()->info.activeVoxels;
    out.withVoxels = byHeat.size();
    const HtmlReportRequest& o = pictures.request;
    for (std::size_t i = 0; i < std::min(o.regionRenders, byHeat.size()); ++i) {
        const std::uint64_t id = byHeat[i]->info.id;
        out.files[id] = pictures.draw("region-" + countText(id), RenderKind::Raycast, id, o.regionWidth, o.regionHeight);
    }
    return out;
}

std::string workDirPage(RenderContext& context, const HtmlReportRequest& o, const fs::path& dir, HtmlReportResult& result) {
    const std::string& input = o.input;
    // The tables need every voxel read (statistics, checksums): that runs on
    // its own thread while this one draws from the region headers' list.
    std::future<StoreSummary> verified = std::async(std::launch::async, [&] { return inspectStore(input, true); });
    const StoreSummary listed = inspectStore(input, false);
    ReportPictures pictures{context, o, dir, openVolumeSource(input)};
    const RegionRenders renders = renderHottestRegions(pictures, listed.regions);
    const std::string volumeRenders = pictures.source->occupiedBricks().empty()
                                          ? "<p>The volume has no active voxels: nothing to render.</p>\n"
                                          : wholeVolumeRenders(pictures);
    const StoreSummary s = verified.get();
    const VoxelGrid& grid = s.manifest.grid;
    result.regions = s.regions.size();

    HtmlRows summary = {
        {"work directory", s.dir},
        {"made by", "yarnvox " + s.manifest.yarnvoxVersion},
        {"grid", std::to_string(grid.dims.x) + " x " + std::to_string(grid.dims.y) + " x " + std::to_string(grid.dims.z) +
                     " voxels of " + numberText("%.6g", grid.voxelSize)},
        {"reduce", toString(s.manifest.reduce)},
        {"run", s.manifest.completeRegions ? "complete" : "not finished"},
    };
    for (const auto& field : runMetadataText(s.manifest.run)) summary.push_back(field);
    const double ratio = s.bytesOnDisk ? double(s.valueBytes) / double(s.bytesOnDisk) : 0.0;
    summary.insert(summary.end(), {{"regions", countText(s.regions.size())},
                                   {"damaged regions", countText(s.badRegions)},
                                   {"bricks", countText(s.bricks)},
                                   {"active voxels", countText(s.activeVoxels)},
                                   {"bytes on disk", bytesText(double(s.bytesOnDisk))},
                                   {"compression ratio", numberText("%.2f", ratio) + " (values " + bytesText(double(s.valueBytes)) + ")"}});

    result.renderedRegions = renders.files.size();

    std::string page = "<h1>yarnvox inspect: " + htmlEscape(fs::path(input).filename().string()) + "</h1>\n";
    page += "<h2 id=\"summary\">Summary</h2>\n" + htmlTable(summary);
    page += stageSection(s.manifest.stageSeconds, s.manifest.completeRegions ? "made by a yarnvox that did not record them"
                                                                             : "the run has not finished");
    page += "<h2 id=\"histogram\">Density</h2>\n" + histogramSvg(s.voxels) + htmlTable(statisticsRows(s.voxels, true));
    page += volumeRenders;

    page += regionHeatSection(renders, s.regions, grid.dims, o.regionRenders);

    page += "<table class=\"regions\">\n<tr><th>region</th><th>min</th><th>max</th><th>bricks</th><th>active voxels</th>"
            "<th>on disk</th><th>ratio</th><th>heat</th><th>render</th></tr>\n";
    for (const RegionRow& r : s.regions) {
        const std::string id = countText(r.info.id);
        page += "<tr id=\"region-" + id + "\"><td>" + id + "</td><td>" + htmlEscape(coordText(r.info.min)) + "</td><td>" +
                htmlEscape(coordText(r.info.max)) + "</td>";
        if (!r.problem.empty()) {
            page += "<td colspan=\"6\" class=\"problem\">" + htmlEscape(r.problem) + "</td></tr>\n";
            continue;
        }
        page += "<td>" + countText(r.info.brickCount) + "</td><td>" + countText(r.info.activeVoxels) + "</td><td>" +
                bytesText(double(r.info.bytesOnDisk)) + "</td><td>" +
                numberText("%.2f", r.info.bytesOnDisk ? double(r.valueBytes) / double(r.info.bytesOnDisk) : 0.0) +
                "</td>" + heatAndRenderCells(renders, r) + "</tr>\n";
    }
    return page + "</table>\n";
}

std::string vdbPage(RenderContext& context, const HtmlReportRequest& o, const fs::path& dir, HtmlReportResult& result) {
    const std::string& input = o.input;
    // The statistics read every voxel on their own thread while this one draws.
    std::future<VdbSummary> summarized = std::async(std::launch::async, [&] { return inspectVdb(input); });
    ReportPictures pictures{context, o, dir, openVolumeSource(input)};
    const std::string volumeRenders = pictures.source->occupiedBricks().empty()
                                          ? "<p>The volume has no active voxels: nothing to render.</p>\n"
                                          : wholeVolumeRenders(pictures);
    const VdbSummary s = summarized.get();
    HtmlRows summary = {{"file", s.path},
                    {"OpenVDB file version", s.libraryVersion},
                    {"bytes on disk", bytesText(double(s.fileBytes))},
                    {"voxel size", numberText("%.6g", s.voxelSize)}};
    for (const auto& [k, v] : s.fileMetadata)
        if (k != "stage_seconds") summary.emplace_back(k, v);
    for (const GridSummary& g : s.grids)
        summary.emplace_back("grid " + g.name, g.type + ", " + countText(g.activeVoxels) + " active voxels in " +
                                                   countText(g.leaves) + " leaves" + (g.halfFloat ? ", stored as half" : ""));
    std::string page = "<h1>yarnvox inspect: " + htmlEscape(fs::path(input).filename().string()) + "</h1>\n";
    page += "<h2 id=\"summary\">Summary</h2>\n" + htmlTable(summary);
    page += stageSection(s.stageSeconds, kVdbStagesNotRecorded);
    page += "<h2 id=\"histogram\">Density</h2>\n" + histogramSvg(s.voxels) + htmlTable(statisticsRows(s.voxels, s.hasOrientation));
    if (s.regions.empty())
        page += "<h2 id=\"regions\">Regions</h2>\n<p>The file has no zoom regions (yarnvox voxelize and merge record "
                "them; a work directory has them): the renders below are of the whole volume.</p>\n";
    page += volumeRenders;
    if (s.regions.empty()) return page;

    // The regions the file records: their boxes and active voxels, no bytes (the store's alone).
    std::vector<RegionRow> regions;
    glm::ivec3 dims(1);
    for (const RecordedRegion& r : s.regions) {
        RegionRow row;
        row.info.id = r.id;
        row.info.min = r.min;
        row.info.max = r.max;
        row.info.activeVoxels = r.activeVoxels;
        regions.push_back(row);
        dims = glm::max(dims, r.max);
    }
    const RegionRenders renders = renderHottestRegions(pictures, regions);
    result.regions = regions.size();
    result.renderedRegions = renders.files.size();
    page += regionHeatSection(renders, regions, dims, o.regionRenders);
    page += "<table class=\"regions\">\n<tr><th>region</th><th>min</th><th>max</th><th>active voxels</th><th>heat</th>"
            "<th>render</th></tr>\n";
    for (const RegionRow& r : regions) {
        const std::string id = countText(r.info.id);
        page += "<tr id=\"region-" + id + "\"><td>" + id + "</td><td>" + htmlEscape(coordText(r.info.min)) + "</td><td>" +
                htmlEscape(coordText(r.info.max)) + "</td><td>" + countText(r.info.activeVoxels) + "</td>" +
                heatAndRenderCells(renders, r) + "</tr>\n";
    }
    return page + "</table>\n";
}

} // namespace

std::string writeHtmlReport(RenderContext& context, const HtmlReportRequest& request) {
    HtmlReportResult result;
    const std::size_t images = writeReportDirectory(request.input, request.dir, [&](const fs::path& building) {
        const std::string body = fs::is_directory(request.input) ? workDirPage(context, request, building, result)
                                                                 : vdbPage(context, request, building, result);
        return htmlPage(request.input, body);
    });
    std::string out;
    appendf(out, "%s/index.html: report with %zu pictures", request.dir.c_str(), images);
    if (result.regions) appendf(out, ", renders of %zu of %zu regions", result.renderedRegions, result.regions);
    return out + "\n";
}

} // namespace yv

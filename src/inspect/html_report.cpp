#include "inspect/html_report.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/stage_seconds.h"
#include "core/text.h"
#include "inspect/inspect_render.h"
#include "inspect/inspect_store.h"
#include "inspect/inspect_vdb.h"
#include "inspect/png_image.h"

#include <glm/common.hpp>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <span>
#include <sstream>
#include <utility>
#include <vector>

namespace yv {
namespace {

namespace fs = std::filesystem;

/// The page's first line: how a later run knows DIR is a report it may replace.
constexpr const char* kReportMarker = "<!DOCTYPE html><!-- yarnvox inspect report -->";

std::string escape(const std::string& text) {
    std::string out;
    for (const char c : text) {
        switch (c) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        default: out += c;
        }
    }
    return out;
}

std::string format(const char* pattern, double v) {
    char text[64];
    std::snprintf(text, sizeof text, pattern, v);
    return text;
}

std::string count(std::uint64_t n) { return std::to_string(n); }

std::string bytes(double b) {
    const char* units[] = {"B", "KB", "MB", "GB", "TB"};
    int u = 0;
    while (b >= 1000.0 && u < 4) b /= 1000.0, ++u;
    return format(u ? "%.2f" : "%.0f", b) + " " + units[u];
}

/// Heat 0..1 as a colour from dark blue through red to yellow.
std::string heatColour(double t) {
    static const double stops[][3] = {{20, 30, 110}, {150, 40, 140}, {230, 80, 40}, {250, 220, 60}};
    t = std::clamp(t, 0.0, 1.0) * 3.0;
    const int i = std::min(2, int(t));
    const double f = t - i;
    char text[16];
    std::snprintf(text, sizeof text, "#%02x%02x%02x", int(stops[i][0] + f * (stops[i + 1][0] - stops[i][0])),
                  int(stops[i][1] + f * (stops[i + 1][1] - stops[i][1])),
                  int(stops[i][2] + f * (stops[i + 1][2] - stops[i][2])));
    return text;
}

using Rows = std::vector<std::pair<std::string, std::string>>;

std::string table(const Rows& rows) {
    std::string s = "<table class=\"kv\">\n";
    for (const auto& [k, v] : rows) s += "<tr><th>" + escape(k) + "</th><td>" + escape(v) + "</td></tr>\n";
    return s + "</table>\n";
}

/// The density histogram as bars of inline SVG, with the share above 1.
std::string histogramSvg(const VoxelStatistics& v) {
    constexpr int barWidth = 48, height = 160, top = 10, base = top + height;
    const std::uint64_t most = std::max<std::uint64_t>(1, *std::max_element(v.histogram.begin(), v.histogram.end()));
    std::string s = "<svg class=\"histogram\" width=\"" + std::to_string(VoxelStatistics::kBins * barWidth + 20) +
                    "\" height=\"" + std::to_string(base + 40) + "\" role=\"img\" aria-label=\"density histogram\">\n";
    for (int i = 0; i < VoxelStatistics::kBins; ++i) {
        const std::uint64_t n = v.histogram[std::size_t(i)];
        const int h = int(double(height) * double(n) / double(most) + 0.5);
        const int x = 10 + i * barWidth;
        const std::string label = i == VoxelStatistics::kBins - 1 ? "> 1" : format("%.1f", v.binHigh(i));
        s += "<rect x=\"" + std::to_string(x + 4) + "\" y=\"" + std::to_string(base - h) + "\" width=\"" +
             std::to_string(barWidth - 8) + "\" height=\"" + std::to_string(h) + "\" fill=\"" +
             (i == VoxelStatistics::kBins - 1 ? "#c03030" : "#4060a0") + "\"><title>" +
             escape((i == VoxelStatistics::kBins - 1 ? std::string("above 1") : format("%.1f", v.binLow(i)) + " - " + label) +
                    ": " + count(n) + " voxels") +
             "</title></rect>\n";
        s += "<text x=\"" + std::to_string(x + barWidth / 2) + "\" y=\"" + std::to_string(base + 16) +
             "\" text-anchor=\"middle\">" + escape(label) + "</text>\n";
    }
    s += "<text x=\"10\" y=\"" + std::to_string(base + 34) + "\">density (upper bound of each bin), bar height: voxels</text>\n";
    return s + "</svg>\n";
}

Rows statisticsRows(const VoxelStatistics& v, bool hasOrientation) {
    Rows rows = {
        {"active voxels counted", count(v.activeVoxels)},
        {"voxels above density 1", count(v.aboveOne) + " (" +
                                       format("%.3g", v.activeVoxels ? 100.0 * double(v.aboveOne) / double(v.activeVoxels) : 0.0) +
                                       " %)"},
        {"largest density", format("%.6g", v.densityMax)},
    };
    if (hasOrientation) {
        const double n = v.unitAxes ? double(v.unitAxes) : 1.0;
        rows.emplace_back("voxels with a unit axis",
                          format("%.4g", v.activeVoxels ? 100.0 * double(v.unitAxes) / double(v.activeVoxels) : 0.0) + " %");
        rows.emplace_back("mean |axis| x, y, z", format("%.3f", v.axisComponentSum.x / n) + ", " +
                                                     format("%.3f", v.axisComponentSum.y / n) + ", " +
                                                     format("%.3f", v.axisComponentSum.z / n));
    }
    return rows;
}

std::string stageSection(const StageSeconds& stages, const std::string& notRecordedWhy) {
    std::string s = "<h2 id=\"stages\">Time per stage</h2>\n";
    if (stages.empty()) return s + "<p>Not recorded (" + escape(notRecordedWhy) + ").</p>\n";
    Rows whole, parts;
    for (const auto& [name, seconds] : stages)
        (isWholeStage(name) ? whole : parts).emplace_back(name, format("%.3f s", seconds));
    whole.emplace_back("all stages", format("%.3f s", wholeStageSum(stages)));
    s += table(whole);
    if (!parts.empty())
        s += "<p>Parts of them, timed on their own threads (they may overlap):</p>\n" + table(parts);
    return s;
}

/// A render of `source` to DIR/renders/NAME.png; empty on a volume without voxels there.
struct Renderer {
    const VolumeSource& source;
    const HtmlReportOptions& options;
    fs::path dir;
    std::size_t images = 0;

    std::string render(const std::string& name, RenderKind kind, std::optional<std::uint64_t> region, int w, int h) {
        RenderRequest r;
        r.kind = kind;
        r.view = options.view;
        r.width = w;
        r.height = h;
        r.region = region;
        r.transferFunction = options.transferFunction;
        r.gpuBudgetBytes = options.gpuBudgetBytes;
        r.device = options.device;
        const RenderReport rep = renderVolume(source, r);
        const std::string file = "renders/" + name + ".png";
        writePng((dir / file).string(), rep.image);
        ++images;
        return file;
    }
};

std::string imageLink(const std::string& file, const std::string& alt, int width) {
    return "<a href=\"" + file + "\"><img src=\"" + file + "\" width=\"" + std::to_string(width) + "\" alt=\"" +
           escape(alt) + "\"></a>";
}

std::string wholeVolumeRenders(Renderer& renderer, bool hasOrientation) {
    const HtmlReportOptions& o = renderer.options;
    std::string s = "<h2 id=\"renders\">The whole volume</h2>\n<div class=\"renders\">\n";
    const int w = o.width / 2;
    s += "<figure>" + imageLink(renderer.render("volume-raycast", RenderKind::Raycast, std::nullopt, o.width, o.height), "ray cast of the whole volume", w) +
         "<figcaption>ray cast (transfer function " + escape(o.transferFunction) + ")</figcaption></figure>\n";
    s += "<figure>" + imageLink(renderer.render("volume-mip", RenderKind::Mip, std::nullopt, o.width, o.height), "maximum intensity projection of the whole volume", w) +
         "<figcaption>maximum density along each ray</figcaption></figure>\n";
    if (hasOrientation)
        s += "<figure>" + imageLink(renderer.render("volume-orientation", RenderKind::Orientation, std::nullopt, o.width, o.height), "orientation of the whole volume", w) +
             "<figcaption>orientation, |axis| as RGB</figcaption></figure>\n";
    return s + "</div>\n";
}

/// The regions seen from above, one panel per z range they share: each
/// region a rectangle coloured by heat that links to its table row.
std::string regionMap(const std::vector<RegionRow>& regions, glm::ivec3 dims, std::uint64_t hottest) {
    std::map<std::pair<int, int>, std::vector<const RegionRow*>> layers;
    for (const RegionRow& r : regions) layers[{r.info.min.z, r.info.max.z}].push_back(&r);
    const double scale = 240.0 / std::max(1, std::max(dims.x, dims.y));
    const int w = int(dims.x * scale + 0.5) + 2, h = int(dims.y * scale + 0.5) + 2;
    std::string s = "<div class=\"map\">\n";
    for (const auto& [z, members] : layers) {
        s += "<figure><svg width=\"" + std::to_string(w) + "\" height=\"" + std::to_string(h) +
             "\" role=\"img\" aria-label=\"regions at z " + std::to_string(z.first) + " to " + std::to_string(z.second) + "\">\n";
        for (const RegionRow* r : members) {
            const double heat = hottest ? double(r->info.activeVoxels) / double(hottest) : 0.0;
            // y grows upwards in the volume, downwards on the page.
            const double x0 = 1 + r->info.min.x * scale, x1 = 1 + r->info.max.x * scale;
            const double y0 = 1 + (dims.y - r->info.max.y) * scale, y1 = 1 + (dims.y - r->info.min.y) * scale;
            const std::string id = count(r->info.id);
            s += "<a href=\"#region-" + id + "\"><rect x=\"" + format("%.2f", x0) + "\" y=\"" + format("%.2f", y0) +
                 "\" width=\"" + format("%.2f", x1 - x0) + "\" height=\"" + format("%.2f", y1 - y0) + "\" fill=\"" +
                 (r->problem.empty() ? heatColour(heat) : std::string("#808080")) +
                 "\" stroke=\"#ffffff\" stroke-width=\"1\"><title>region " + id + ": " +
                 (r->problem.empty() ? count(r->info.activeVoxels) + " active voxels" : escape(r->problem)) +
                 "</title></rect></a>\n";
        }
        s += "</svg><figcaption>z " + std::to_string(z.first) + " to " + std::to_string(z.second) + "</figcaption></figure>\n";
    }
    return s + "</div>\n";
}

/// Ray casts of the hottest regions (most active voxels), --html-renders of them.
struct RegionRenders {
    std::uint64_t hottest = 0;       ///< the most active voxels of a sound region
    std::size_t withVoxels = 0;      ///< sound regions with active voxels
    std::map<std::uint64_t, std::string> files; ///< by region id
};

RegionRenders renderHottestRegions(Renderer& renderer, const std::vector<RegionRow>& regions) {
    std::vector<const RegionRow*> byHeat;
    for (const RegionRow& r : regions)
        if (r.problem.empty() && r.info.activeVoxels > 0) byHeat.push_back(&r);
    std::stable_sort(byHeat.begin(), byHeat.end(),
                     [](const RegionRow* a, const RegionRow* b) { return a->info.activeVoxels > b->info.activeVoxels; });
    RegionRenders out;
    out.hottest = byHeat.empty() ? 0 : byHeat.front()->info.activeVoxels;
    out.withVoxels = byHeat.size();
    const HtmlReportOptions& o = renderer.options;
    for (std::size_t i = 0; i < std::min(o.regionRenders, byHeat.size()); ++i) {
        const std::uint64_t id = byHeat[i]->info.id;
        out.files[id] = renderer.render("region-" + count(id), RenderKind::Raycast, id, o.regionWidth, o.regionHeight);
    }
    return out;
}

/// The heading, the words and the map of the regions by heat.
std::string regionHeatSection(const RegionRenders& renders, const std::vector<RegionRow>& regions, glm::ivec3 dims,
                              std::size_t asked) {
    return "<h2 id=\"regions\">Regions by heat</h2>\n<p>Each zoom region seen from above (+y up), one panel per z range; "
           "colour: its active voxels against the hottest region's " + count(renders.hottest) +
           " (dark blue few, yellow most; grey: damaged). A region links to its row in the table below. " +
           (renders.withVoxels > renders.files.size()
                ? "Renders: the " + count(renders.files.size()) + " hottest of " + count(regions.size()) +
                      " regions (--html-renders " + count(asked) + ")."
                : std::string("Every region with active voxels has a render.")) +
           "</p>\n" + regionMap(regions, dims, renders.hottest);
}

/// A region's heat and render cells.
std::string heatAndRenderCells(const RegionRenders& renders, const RegionRow& r) {
    const double heat = renders.hottest ? double(r.info.activeVoxels) / double(renders.hottest) : 0.0;
    std::string s = "<td style=\"background:" + heatColour(heat) + ";color:" + (heat > 0.6 ? "#000" : "#fff") + "\">" +
                    format("%.2f", heat) + "</td><td>";
    if (const auto it = renders.files.find(r.info.id); it != renders.files.end())
        s += imageLink(it->second, "ray cast of region " + count(r.info.id), 160);
    else
        s += r.info.activeVoxels ? "not rendered (not among the hottest)" : "empty";
    return s + "</td>";
}

std::string workDirPage(const std::string& input, const HtmlReportOptions& o, const fs::path& dir, HtmlReportResult& result) {
    const StoreSummary s = inspectStore(input, true);
    const VoxelGrid& grid = s.manifest.grid;
    const std::unique_ptr<VolumeSource> source = openVolumeSource(input);
    Renderer renderer{*source, o, dir};
    result.regions = s.regions.size();

    Rows summary = {
        {"work directory", s.dir},
        {"made by", "yarnvox " + s.manifest.yarnvoxVersion},
        {"grid", std::to_string(grid.dims.x) + " x " + std::to_string(grid.dims.y) + " x " + std::to_string(grid.dims.z) +
                     " voxels of " + format("%.6g", grid.voxelSize)},
        {"reduce", toString(s.manifest.reduce)},
        {"run", s.manifest.completeRegions ? "complete" : "not finished"},
    };
    for (const auto& field : runMetadataText(s.manifest.run)) summary.push_back(field);
    const double ratio = s.bytesOnDisk ? double(s.valueBytes) / double(s.bytesOnDisk) : 0.0;
    summary.insert(summary.end(), {{"regions", count(s.regions.size())},
                                   {"damaged regions", count(s.badRegions)},
                                   {"bricks", count(s.bricks)},
                                   {"active voxels", count(s.activeVoxels)},
                                   {"bytes on disk", bytes(double(s.bytesOnDisk))},
                                   {"compression ratio", format("%.2f", ratio) + " (values " + bytes(double(s.valueBytes)) + ")"}});

    const RegionRenders renders = renderHottestRegions(renderer, s.regions);
    result.renderedRegions = renders.files.size();

    std::string page = "<h1>yarnvox inspect: " + escape(fs::path(input).filename().string()) + "</h1>\n";
    page += "<h2 id=\"summary\">Summary</h2>\n" + table(summary);
    page += stageSection(s.manifest.stageSeconds, s.manifest.completeRegions ? "made by a yarnvox that did not record them"
                                                                             : "the run has not finished");
    page += "<h2 id=\"histogram\">Density</h2>\n" + histogramSvg(s.voxels) + table(statisticsRows(s.voxels, true));
    if (source->occupiedBricks().empty()) page += "<p>The volume has no active voxels: nothing to render.</p>\n";
    else page += wholeVolumeRenders(renderer, source->hasOrientation());

    page += regionHeatSection(renders, s.regions, grid.dims, o.regionRenders);

    page += "<table class=\"regions\">\n<tr><th>region</th><th>min</th><th>max</th><th>bricks</th><th>active voxels</th>"
            "<th>on disk</th><th>ratio</th><th>heat</th><th>render</th></tr>\n";
    for (const RegionRow& r : s.regions) {
        const std::string id = count(r.info.id);
        page += "<tr id=\"region-" + id + "\"><td>" + id + "</td><td>" + escape(coordText(r.info.min)) + "</td><td>" +
                escape(coordText(r.info.max)) + "</td>";
        if (!r.problem.empty()) {
            page += "<td colspan=\"6\" class=\"problem\">" + escape(r.problem) + "</td></tr>\n";
            continue;
        }
        page += "<td>" + count(r.info.brickCount) + "</td><td>" + count(r.info.activeVoxels) + "</td><td>" +
                bytes(double(r.info.bytesOnDisk)) + "</td><td>" +
                format("%.2f", r.info.bytesOnDisk ? double(r.valueBytes) / double(r.info.bytesOnDisk) : 0.0) +
                "</td>" + heatAndRenderCells(renders, r) + "</tr>\n";
    }
    return page + "</table>\n";
}

std::string vdbPage(const std::string& input, const HtmlReportOptions& o, const fs::path& dir, HtmlReportResult& result) {
    const VdbSummary s = inspectVdb(input);
    const std::unique_ptr<VolumeSource> source = openVolumeSource(input);
    Renderer renderer{*source, o, dir};
    Rows summary = {{"file", s.path},
                    {"OpenVDB file version", s.libraryVersion},
                    {"bytes on disk", bytes(double(s.fileBytes))},
                    {"voxel size", format("%.6g", s.voxelSize)}};
    for (const auto& [k, v] : s.fileMetadata)
        if (k != "stage_seconds") summary.emplace_back(k, v);
    for (const GridSummary& g : s.grids)
        summary.emplace_back("grid " + g.name, g.type + ", " + count(g.activeVoxels) + " active voxels in " +
                                                   count(g.leaves) + " leaves" + (g.halfFloat ? ", stored as half" : ""));
    std::string page = "<h1>yarnvox inspect: " + escape(fs::path(input).filename().string()) + "</h1>\n";
    page += "<h2 id=\"summary\">Summary</h2>\n" + table(summary);
    page += stageSection(s.stageSeconds, kVdbStagesNotRecorded);
    page += "<h2 id=\"histogram\">Density</h2>\n" + histogramSvg(s.voxels) + table(statisticsRows(s.voxels, s.hasOrientation));
    if (s.regions.empty())
        page += "<h2 id=\"regions\">Regions</h2>\n<p>The file has no zoom regions (yarnvox voxelize and merge record "
                "them; a work directory has them): the renders below are of the whole volume.</p>\n";
    if (source->occupiedBricks().empty()) page += "<p>The volume has no active voxels: nothing to render.</p>\n";
    else page += wholeVolumeRenders(renderer, source->hasOrientation());
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
    const RegionRenders renders = renderHottestRegions(renderer, regions);
    result.regions = regions.size();
    result.renderedRegions = renders.files.size();
    page += regionHeatSection(renders, regions, dims, o.regionRenders);
    page += "<table class=\"regions\">\n<tr><th>region</th><th>min</th><th>max</th><th>active voxels</th><th>heat</th>"
            "<th>render</th></tr>\n";
    for (const RegionRow& r : regions) {
        const std::string id = count(r.info.id);
        page += "<tr id=\"region-" + id + "\"><td>" + id + "</td><td>" + escape(coordText(r.info.min)) + "</td><td>" +
                escape(coordText(r.info.max)) + "</td><td>" + count(r.info.activeVoxels) + "</td>" +
                heatAndRenderCells(renders, r) + "</tr>\n";
    }
    return page + "</table>\n";
}

constexpr const char* kStyle =
    "body{font-family:sans-serif;margin:2em;max-width:72em;color:#222}"
    "table{border-collapse:collapse;margin:0.5em 0}th,td{border:1px solid #ccc;padding:0.2em 0.6em;text-align:left}"
    "table.kv th{background:#f2f2f2;font-weight:normal}.problem{color:#b00000}"
    ".renders,.map{display:flex;flex-wrap:wrap;gap:1em}figure{margin:0}figcaption{font-size:85%;color:#555}"
    "svg text{font-size:12px;fill:#333}tr:target{outline:3px solid #e08000}";

/// Whether `dir` may be replaced by a report: an empty directory or an earlier report.
bool replaceable(const fs::path& dir) {
    if (fs::is_empty(dir)) return true;
    std::ifstream in(dir / "index.html");
    std::string first;
    std::getline(in, first);
    return first == kReportMarker;
}

} // namespace

HtmlReportResult writeHtmlReport(const std::string& input, const std::string& dirText, const HtmlReportOptions& options) {
    fs::path dir = fs::path(dirText).lexically_normal();
    if (!dir.has_filename() && dir.has_parent_path()) dir = dir.parent_path(); // "report/"
    std::error_code ec;
    if (dir.filename().empty() || dir.filename() == "." || dir.filename() == "..")
        throw Error("--html " + dirText + ": expected the path of a directory to create");
    if (fs::is_symlink(dir, ec)) throw Error("--html " + dirText + ": is a symbolic link: refusing to replace it");
    if (fs::exists(dir, ec)) {
        if (!fs::is_directory(dir)) throw Error("--html " + dirText + ": exists and is not a directory");
        if (!replaceable(dir))
            throw Error("--html " + dirText + ": the directory holds files that are not a yarnvox report: refusing to replace it");
    }
    const fs::path parent = dir.has_parent_path() ? dir.parent_path() : fs::path(".");
    if (!fs::is_directory(parent, ec)) throw Error("--html " + dirText + ": the directory " + parent.string() + " does not exist");
    const fs::path inputPath = fs::weakly_canonical(input, ec);
    const fs::path outPath = fs::weakly_canonical(dir, ec);
    if (fs::is_directory(input) && std::mismatch(inputPath.begin(), inputPath.end(), outPath.begin(), outPath.end()).first == inputPath.end())
        throw Error("--html " + dirText + ": is inside the work directory " + input + ": choose a place outside it");

    // Built beside its final place, renamed into it at the end.
    const fs::path building = parent / (dir.filename().string() + ".tmp-" + std::to_string(::getpid()));
    fs::remove_all(building, ec);
    HtmlReportResult result;
    try {
        fs::create_directories(building / "renders");
        const std::string body = fs::is_directory(input) ? workDirPage(input, options, building, result)
                                                          : vdbPage(input, options, building, result);
        const std::string page = std::string(kReportMarker) + "\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>yarnvox inspect: " +
                                 escape(fs::path(input).filename().string()) + "</title><style>" + kStyle +
                                 "</style></head><body>\n" + body + "</body></html>\n";
        writeFileAtomically((building / "index.html").string(),
                            std::span(reinterpret_cast<const std::uint8_t*>(page.data()), page.size()));
        result.images = std::size_t(std::distance(fs::directory_iterator(building / "renders"), fs::directory_iterator()));
        if (fs::exists(dir)) {
            const fs::path old = parent / (dir.filename().string() + ".old-" + std::to_string(::getpid()));
            fs::rename(dir, old);
            fs::rename(building, dir);
            fs::remove_all(old, ec);
        } else {
            fs::rename(building, dir);
        }
    } catch (const fs::filesystem_error& e) {
        fs::remove_all(building, ec);
        throw Error("--html " + dirText + ": " + e.what());
    } catch (...) {
        fs::remove_all(building, ec);
        throw;
    }
    return result;
}

} // namespace yv

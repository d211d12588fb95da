#include "inspect/html_page.h"

#include <glm/common.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>

namespace yv {

std::string htmlEscape(const std::string& text) {
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

std::string numberText(const char* pattern, double v) {
    char text[64];
    std::snprintf(text, sizeof text, pattern, v);
    return text;
}

std::string countText(std::uint64_t n) { return std::to_string(n); }

/// Heat 0..1 as a colour from dark blue through red to yellow.
std::string heatColourHex(double t) {
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

using HtmlRows = std::vector<std::pair<std::string, std::string>>;

std::string htmlTable(const HtmlRows& rows) {
    std::string s = "<table class=\"kv\">\n";
    for (const auto& [k, v] : rows) s += "<tr><th>" + htmlEscape(k) + "</th><td>" + htmlEscape(v) + "</td></tr>\n";
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
        const std::string label = i == VoxelStatistics::kBins - 1 ? "> 1" : numberText("%.1f", v.binHigh(i));
        s += "<rect x=\"" + std::to_string(x + 4) + "\" y=\"" + std::to_string(base - h) + "\" width=\"" +
             std::to_string(barWidth - 8) + "\" height=\"" + std::to_string(h) + "\" fill=\"" +
             (i == VoxelStatistics::kBins - 1 ? "#c03030" : "#4060a0") + "\"><title>" +
             htmlEscape((i == VoxelStatistics::kBins - 1 ? std::string("above 1") : numberText("%.1f", v.binLow(i)) + " - " + label) +
                    ": " + countText(n) + " voxels") +
             "</title></rect>\n";
        s += "<text x=\"" + std::to_string(x + barWidth / 2) + "\" y=\"" + std::to_string(base + 16) +
             "\" text-anchor=\"middle\">" + htmlEscape(label) + "</text>\n";
    }
    s += "<text x=\"10\" y=\"" + std::to_string(base + 34) + "\">density (upper bound of each bin), bar height: voxels</text>\n";
    return s + "</svg>\n";
}

HtmlRows statisticsRows(const VoxelStatistics& v, bool hasOrientation) {
    HtmlRows rows = {
        {"active voxels counted", countText(v.activeVoxels)},
        {"voxels above density 1", countText(v.aboveOne) + " (" +
                                       numberText("%.3g", v.activeVoxels ? 100.0 * double(v.aboveOne) / double(v.activeVoxels) : 0.0) +
                                       " %)"},
        {"largest density", numberText("%.6g", double(v.densityMax))},
    };
    if (hasOrientation) {
        const double n = v.unitAxes ? double(v.unitAxes) : 1.0;
        rows.emplace_back("voxels with a unit axis",
                          numberText("%.4g", v.activeVoxels ? 100.0 * double(v.unitAxes) / double(v.activeVoxels) : 0.0) + " %");
        rows.emplace_back("mean |axis| x, y, z", numberText("%.3f", v.axisComponentSum().x / n) + ", " +
                                                     numberText("%.3f", v.axisComponentSum().y / n) + ", " +
                                                     numberText("%.3f", v.axisComponentSum().z / n));
    }
    return rows;
}

std::string stageSection(const StageSeconds& stages, const std::string& notRecordedWhy) {
    std::string s = "<h2 id=\"stages\">Time per stage</h2>\n";
    if (stages.empty()) return s + "<p>Not recorded (" + htmlEscape(notRecordedWhy) + ").</p>\n";
    HtmlRows whole, parts;
    for (const auto& [name, seconds] : stages)
        (isWholeStage(name) ? whole : parts).emplace_back(name, numberText("%.3f s", seconds));
    whole.emplace_back("all stages", numberText("%.3f s", wholeStageSum(stages)));
    s += htmlTable(whole);
    if (!parts.empty())
        s += "<p>Parts of them, timed on their own threads (they may overlap):</p>\n" + htmlTable(parts);
    return s;
}

std::string imageLink(const std::string& file, const std::string& alt, int width) {
    return "<a href=\"" + file + "\"><img src=\"" + file + "\" width=\"" + std::to_string(width) + "\" alt=\"" +
           htmlEscape(alt) + "\"></a>";
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
            const std::string id = countText(r->info.id);
            s += "<a href=\"#region-" + id + "\"><rect x=\"" + numberText("%.2f", x0) + "\" y=\"" + numberText("%.2f", y0) +
                 "\" width=\"" + numberText("%.2f", x1 - x0) + "\" height=\"" + numberText("%.2f", y1 - y0) + "\" fill=\"" +
                 (r->problem.empty() ? heatColourHex(heat) : std::string("#808080")) +
                 "\" stroke=\"#ffffff\" stroke-width=\"1\"><title>region " + id + ": " +
                 (r->problem.empty() ? countText(r->info.activeVoxels) + " active voxels" : htmlEscape(r->problem)) +
                 "</title></rect></a>\n";
        }
        s += "</svg><figcaption>z " + std::to_string(z.first) + " to " + std::to_string(z.second) + "</figcaption></figure>\n";
    }
    return s + "</div>\n";
}

/// The heading, the words and the map of the regions by heat.
std::string regionHeatSection(const RegionRenders& renders, const std::vector<RegionRow>& regions, glm::ivec3 dims,
                              std::size_t asked) {
    return "<h2 id=\"regions\">Regions by heat</h2>\n<p>Each zoom region seen from above (+y up), one panel per z range; "
           "colour: its active voxels against the hottest region's " + countText(renders.hottest) +
           " (dark blue few, yellow most; grey: damaged). A region links to its row in the table below. " +
           (renders.withVoxels > renders.files.size()
                ? "Renders: the " + countText(renders.files.size()) + " hottest of " + countText(regions.size()) +
                      " regions (--html-renders " + countText(asked) + ")."
                : std::string("Every region with active voxels has a render.")) +
           "</p>\n" + regionMap(regions, dims, renders.hottest);
}

/// A region's heat and render cells.
std::string heatAndRenderCells(const RegionRenders& renders, const RegionRow& r) {
    const double heat = renders.hottest ? double(r.info.activeVoxels) / double(renders.hottest) : 0.0;
    std::string s = "<td style=\"background:" + heatColourHex(heat) + ";color:" + (heat > 0.6 ? "#000" : "#fff") + "\">" +
                    numberText("%.2f", heat) + "</td><td>";
    if (const auto it = renders.files.find(r.info.id); it != renders.files.end())
        s += imageLink(it->second, "ray cast of region " + countText(r.info.id), 160);
    else
        s += r.info.activeVoxels ? "not rendered (not among the hottest)" : "empty";
    return s + "</td>";
}

namespace {

constexpr const char* kStyle =
    "body{font-family:sans-serif;margin:2em;max-width:72em;color:#222}"
    "table{border-collapse:collapse;margin:0.5em 0}th,td{border:1px solid #ccc;padding:0.2em 0.6em;text-align:left}"
    "table.kv th{background:#f2f2f2;font-weight:normal}.problem{color:#b00000}"
    ".renders,.map{display:flex;flex-wrap:wrap;gap:1em}figure{margin:0}figcaption{font-size:85%;color:#555}"
    "svg text{font-size:12px;fill:#333}tr:target{outline:3px solid #e08000}";

} // namespace

std::string htmlPage(const std::string& input, const std::string& body) {
    return std::string(kReportMarker) + "\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>yarnvox inspect: " +
           htmlEscape(std::filesystem::path(input).filename().string()) + "</title><style>" + kStyle +
           "</style></head><body>\n" + body + "</body></html>\n";
}

} // namespace yv

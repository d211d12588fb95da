// The pieces of `inspect --html`'s page that need no GL: escaping, tables,
// the density histogram as inline SVG, the time per stage, the map of the
// zoom regions coloured by heat and the cells of the region table. The
// renders they link to come from the render layer (render/html_report.h).
#pragma once

#include "core/stage_seconds.h"
#include "inspect/inspect_store.h"
#include "core/voxel_statistics.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace yv {

/// The page's first line: how a later run knows a directory is a report it may replace.
constexpr const char* kReportMarker = "<!DOCTYPE html><!-- yarnvox inspect report -->";

/// `text` with &, <, > and " as entities.
std::string htmlEscape(const std::string& text);

/// One number printf-formatted by `pattern`.
std::string numberText(const char* pattern, double v);

/// A count in decimal.
std::string countText(std::uint64_t n);

/// Heat 0..1 as an HTML colour from dark blue through red to yellow.
std::string heatColourHex(double t);

/// Rows of a two-column table: name, value.
using HtmlRows = std::vector<std::pair<std::string, std::string>>;

/// The rows as a table of names and values (escaped).
std::string htmlTable(const HtmlRows& rows);

/// The density histogram as bars of inline SVG, with the share above 1.
std::string histogramSvg(const VoxelStatistics& v);

/// The statistics below the histogram (and the orientation's, where the volume has one).
HtmlRows statisticsRows(const VoxelStatistics& v, bool hasOrientation);

/// The section of the time per stage, or why none was recorded.
std::string stageSection(const StageSeconds& stages, const std::string& notRecordedWhy);

/// A picture `width` pixels wide that links to its file.
std::string imageLink(const std::string& file, const std::string& alt, int width);

/// The regions seen from above, one panel per z range they share: each
/// region a rectangle coloured by heat that links to its table row.
std::string regionMap(const std::vector<RegionRow>& regions, glm::ivec3 dims, std::uint64_t hottest);

/// Ray casts of the hottest regions (most active voxels), --html-renders of them.
struct RegionRenders {
    std::uint64_t hottest = 0;                  ///< the most active voxels of a sound region
    std::size_t withVoxels = 0;                 ///< sound regions with active voxels
    std::map<std::uint64_t, std::string> files; ///< by region id
};

/// The heading, the words and the map of the regions by heat.
std::string regionHeatSection(const RegionRenders& renders, const std::vector<RegionRow>& regions, glm::ivec3 dims,
                              std::size_t asked);

/// A region's heat and render cells.
std::string heatAndRenderCells(const RegionRenders& renders, const RegionRow& r);

/// The whole page: the marker line, the head titled after `input`'s file name, and `body`.
std::string htmlPage(const std::string& input, const std::string& body);

} // namespace yv

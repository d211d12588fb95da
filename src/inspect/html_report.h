// `yarnvox inspect PATH --html DIR`: a self-contained report of a work
// directory or a .vdb that a browser opens from disk: the summary, the
// density histogram and the time per stage, a map of the zoom regions
// coloured by heat whose every region links to its row of the region table,
// and ray-cast renders (PNG files beside the page) of the whole volume and of
// the hottest regions. Built in a temporary directory renamed into place, so
// DIR is either the old report, absent, or the complete new one.
#pragma once

#include "inspect/camera.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace yv {

struct HtmlReportOptions {
    std::size_t regionRenders = 8; ///< regions rendered, the hottest first (0: none)
    ViewAngles view;
    int width = 640, height = 480;          ///< the whole-volume renders
    int regionWidth = 320, regionHeight = 240; ///< each region's render
    std::string transferFunction = "fibre";
    std::uint64_t gpuBudgetBytes = 512ull << 20;
    int device = -1;
};

struct HtmlReportResult {
    std::size_t regions = 0;         ///< in the work directory, or recorded in the .vdb (0 where none)
    std::size_t renderedRegions = 0; ///< of them, with renders on the page
    std::size_t images = 0;          ///< PNG files written
};

/// Writes the report for `input` (a work directory or a .vdb) to `dir`.
/// `dir` may be absent or an earlier report (replaced); anything else is
/// refused. Throws yv::Error; on failure no `dir` is left that looks complete.
HtmlReportResult writeHtmlReport(const std::string& input, const std::string& dir, const HtmlReportOptions& options);

} // namespace yv

// `yarnvox inspect PATH --html DIR`: a self-contained report of a work
// directory or a .vdb that a browser opens from disk: the summary, the
// density histogram and the time per stage, a map of the zoom regions
// coloured by heat whose every region links to its row of the region table,
// and ray-cast renders (PNG files beside the page) of the whole volume and of
// the hottest regions, drawn on the context the command lends. The page's
// pieces are inspect/html_page.h's; the directory is replaced as
// inspect/report_directory.h says.
#pragma once

#include "inspect/camera.h"
#include "inspect/transfer_function.h"
#include "render/render_context.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace yv {

struct HtmlReportRequest {
    std::string input; ///< a work directory or a .vdb
    std::string dir;   ///< where the report goes
    std::size_t regionRenders = 8; ///< regions rendered, the hottest first (0: none)
    ViewAngles view;
    int width = 640, height = 480;             ///< the whole-volume renders
    int regionWidth = 320, regionHeight = 240; ///< each region's render
    TransferFunction transferFunction = defaultTransferFunction();
    std::string transferFunctionName = "fibre"; ///< as --tf named it, for the captions
    std::uint64_t gpuBudgetBytes = 512ull << 20;
};

/// Writes the report `request` asks for and returns the line inspect prints
/// about it (the pictures written, the regions rendered). Throws yv::Error;
/// on failure no report directory is left that looks complete.
std::string writeHtmlReport(RenderContext& context, const HtmlReportRequest& request);

} // namespace yv

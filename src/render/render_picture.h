// `yarnvox inspect PATH --render MODE -o FILE.png`: the picture written, and
// what inspect prints about it (text, or one JSON object). The volume's
// renders, the run's slices found again, and a garment's slices as volumetric
// triangles, straight from a .bcc or from the garment a volume was made from.
#pragma once

#include "inspect/render_request.h"
#include "inspect/run_slices.h"
#include "pipeline/preview_slices.h"
#include "render/render_context.h"

#include <string>

namespace yv {

struct PictureRequest {
    std::string input;  ///< a work directory, a .vdb, or (volumetric-triangles) a .bcc garment
    std::string output; ///< the PNG, replaced atomically
    RenderRequest render;
    std::string viewText, cutText; ///< --view and --cut as given, echoed in what is printed
    bool regions = false;          ///< --regions: outline the zoom regions (render.outlines is filled here)
    RunSlicesOptions runSlices;    ///< slices: --garment, --yarn-radius
    PreviewSliceOptions preview;   ///< volumetric-triangles: how the garment is sliced (with --yarn-radius)
    bool json = false;
};

/// Draws the picture `request` asks for on `context`, writes it, and returns
/// what inspect prints. Throws yv::Error (the input lacks what the mode
/// needs: a garment, a region, voxels; no GL context).
std::string renderPicture(RenderContext& context, const PictureRequest& request);

} // namespace yv

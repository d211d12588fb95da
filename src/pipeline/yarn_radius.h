// Which yarn radius a run uses, and where it came from (the .vdb records both).
#pragma once

#include "garment/cross_section.h"
#include "garment/garment.h"

#include <string>

namespace yv {

struct YarnRadiusChoice {
    double radius = 0.0;
    std::string source;      ///< "option", "cross-section", "file" or "estimated"
    std::string description; ///< for messages: "--yarn-radius 0.1", "estimated from GARMENT", ...
    std::string note;        ///< a line for stderr when the radius was estimated, else ""
};

/// --yarn-radius when given (`option` > 0), else the cross-section PNG's
/// yarn-radius text, else the garment file's, else estimated from the
/// garment (estimateYarnRadius). Throws yv::Error naming `input` when there
/// is none and the garment gives no evidence either.
YarnRadiusChoice chooseYarnRadius(double option, const CrossSection& xs, const Garment& garment, const std::string& input);

} // namespace yv

#include "pipeline/yarn_radius.h"

#include "core/error.h"
#include "core/world_units.h"
#include "garment/radius_estimate.h"

namespace yv {

YarnRadiusChoice chooseYarnRadius(double option, const CrossSection& xs, const Garment& garment, const std::string& input) {
    if (option > 0.0) return {option, "option", "--yarn-radius " + numberText(option), ""};
    if (xs.radius > 0.0) return {xs.radius, "cross-section", "yarn-radius of " + xs.name, ""};
    if (garment.yarnRadius > 0.0) return {garment.yarnRadius, "file", "yarn-radius of " + input, ""};

    const RadiusEstimate estimate = estimateYarnRadius(garment);
    if (!(estimate.radius > 0.0))
        throw Error(input + ": the file gives no yarn radius and no yarn comes near another to estimate one from: "
                            "pass --yarn-radius R (world units)");
    if (const std::string problem = lengthProblem(estimate.radius); !problem.empty())
        throw Error(input + ": the yarn radius estimated from the garment, " + problem + ": pass --yarn-radius R");
    return {estimate.radius, "estimated", "estimated from " + input,
            input + ": the file gives no yarn radius; estimated " + numberText(estimate.radius) +
                " (half the median closest approach of " + std::to_string(estimate.contacts) +
                " places where yarns meet; --yarn-radius overrides it)"};
}

} // namespace yv

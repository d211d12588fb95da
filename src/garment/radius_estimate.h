// Most real garment files give no yarn radius. Yarns that touch lie two radii
// apart, centre to centre, so the radius can be read off the garment itself.
#pragma once

#include "garment/garment.h"

#include <cstddef>

namespace yv {

struct RadiusEstimate {
    double radius = 0.0;      ///< 0: the garment gives no evidence (no yarn comes near another)
    std::size_t samples = 0;  ///< points sampled along the curves
    std::size_t contacts = 0; ///< closest approaches the estimate is the median of
};

/// Estimates the yarn radius from where yarns touch: points are sampled along
/// every curve, each finds the nearest piece of another yarn (or of its own
/// yarn, far from it along the yarn: a knit loop touching its neighbour), and
/// the closest approaches (local minima of that distance along each yarn) are
/// taken as contacts. The radius is half their median: robust to a few
/// interpenetrating or far-apart places. Exact for parallel touching yarns.
RadiusEstimate estimateYarnRadius(const Garment& garment);

} // namespace yv

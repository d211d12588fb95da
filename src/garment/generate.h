// Procedural yarn-level garments for tests, demos and benchmarks.
#pragma once

#include "garment/garment.h"

#include <cstdint>
#include <string>

namespace yv {

enum class WeavePattern { Plain, Twill, Satin, Knit };
enum class GarmentShape { Flat, Cylinder, Sphere };

struct GenerateOptions {
    WeavePattern pattern = WeavePattern::Plain;
    GarmentShape shape = GarmentShape::Flat;
    /// Target number of yarn crossings (woven: warp x weft crossings; knit:
    /// loop-to-loop contacts). The generator picks a near-square grid.
    std::uint64_t crossings = 1000;
    std::uint64_t seed = 1;
    /// Distance between neighbouring parallel yarns, world units.
    double yarnSpacing = 1.0;
    /// Yarn radius recorded in the garment (world units).
    double yarnRadius = 0.3;
    /// Random jitter of control points, as a fraction of yarnSpacing.
    double jitter = 0.02;
};

/// Builds a deterministic garment: the same options give the same points, bit for bit.
Garment generateGarment(const GenerateOptions& options);

WeavePattern parseWeavePattern(const std::string& s); // throws yv::Error on unknown names
GarmentShape parseGarmentShape(const std::string& s);
const char* toString(WeavePattern p);
const char* toString(GarmentShape s);

} // namespace yv

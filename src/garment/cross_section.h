// The fibre-density distribution on a slice (the paper's Figure 1): a square
// 2D texture spanning [-radius, radius]^2 in slice-local coordinates.
#pragma once

#include "core/footprint.h"

#include <glm/vec2.hpp>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace yv {

struct CrossSection {
    int size = 0;                      ///< texels per side
    std::vector<std::uint8_t> density; ///< size*size, row y-major; 255 = solid fibre
    double radius = 0.0;               ///< yarn radius the file asks for (0: none)
    std::string name;
    /// The uniform disk: coverage is computed exactly from the circle, not
    /// from the texture (which stays for the heat map and for pictures).
    bool analyticDisk = false;

    /// Sub-samples per footprint side for texture cross-sections.
    static constexpr int kFootprintSamples = 4;

    /// Texel for slice-local (u, v) in [-1, 1]^2 (local coordinate / radius),
    /// nearest texel at level 0, clamped at the border. Shaders use the same rule.
    std::uint8_t lookup(double u, double v) const {
        int ix = static_cast<int>(std::floor((u + 1.0) * 0.5 * size));
        int iy = static_cast<int>(std::floor((v + 1.0) * 0.5 * size));
        ix = ix < 0 ? 0 : (ix >= size ? size - 1 : ix);
        iy = iy < 0 ? 0 : (iy >= size ? size - 1 : iy);
        return density[static_cast<std::size_t>(iy) * size + ix];
    }
    /// Texel for (u, v), and 0 outside the square [-1, 1)^2.
    std::uint8_t lookupInside(double u, double v) const {
        return u >= -1.0 && u < 1.0 && v >= -1.0 && v < 1.0 ? lookup(u, v) : 0;
    }
    /// Mean density over a sample's footprint: the parallelogram centred at
    /// slice-local `c` with edges `e0`, `e1`, all in units of the yarn radius.
    /// The disk: exact coverage. A texture: the mean of kFootprintSamples^2
    /// texels at the centres of a regular grid over the footprint.
    double footprintDensity(glm::dvec2 c, glm::dvec2 e0, glm::dvec2 e1) const {
        if (analyticDisk) return diskCoverage(c, e0, e1, 1.0);
        constexpr int n = kFootprintSamples;
        int sum = 0;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const glm::dvec2 p = c + ((i + 0.5) / n - 0.5) * e0 + ((j + 0.5) / n - 0.5) * e1;
                sum += lookupInside(p.x, p.y);
            }
        return sum / (255.0 * n * n);
    }
    /// Mean density over the square (fraction of the square filled by fibre).
    double meanDensity() const;
};

/// Uniform density 1 inside the unit disk; edge texels hold their coverage.
CrossSection makeDiskCrossSection(int size = 128);

/// Procedural plies of fibres like the paper's Figure 1: three plies, each a
/// bundle of small round fibres, denser towards the ply centre.
CrossSection makeFiberCrossSection(int size = 128, std::uint64_t seed = 7);

/// Loads a PNG; its alpha channel (or grey level where there is no alpha) is
/// the density. A tEXt chunk "yarn-radius" sets CrossSection::radius.
CrossSection loadCrossSectionPng(const std::string& path);

/// "fibers", "disk" or a path to a PNG file.
CrossSection makeCrossSection(const std::string& spec);

} // namespace yv

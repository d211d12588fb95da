// The fibre-density distribution on a slice (the paper's Figure 1): a square
// 2D texture spanning [-radius, radius]^2 in slice-local coordinates.
#pragma once

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

    /// Texel for slice-local (u, v) in [-1, 1]^2 (local coordinate / radius),
    /// nearest texel at level 0, clamped at the border. Shaders use the same rule.
    std::uint8_t lookup(double u, double v) const {
        int ix = static_cast<int>(std::floor((u + 1.0) * 0.5 * size));
        int iy = static_cast<int>(std::floor((v + 1.0) * 0.5 * size));
        ix = ix < 0 ? 0 : (ix >= size ? size - 1 : ix);
        iy = iy < 0 ? 0 : (iy >= size ? size - 1 : iy);
        return density[static_cast<std::size_t>(iy) * size + ix];
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

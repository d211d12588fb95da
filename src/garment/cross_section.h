// The fibre-density distribution on a slice (the paper's Figure 1): a square
// 2D texture spanning [-radius, radius]^2 in slice-local coordinates.
#pragma once

#include "core/footprint.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

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

    /// The fibres' colour (--albedo): linear RGB in [0, 1] per texel, times
    /// the texel's density (premultiplied, so that bilinear lookups weigh each
    /// texel's colour by its fibre); empty when the run has no albedo.
    std::vector<glm::vec3> albedo;

    bool hasAlbedo() const { return !albedo.empty(); }

    /// Sub-cells per side of a sample's footprint (see footprintDensity).
    static constexpr int kFootprintCells = 4;

    /// Density at (u, v) in [-1, 1)^2 by bilinear interpolation of the texel
    /// centres (clamped at the border), 0 outside the square. Continuous, so
    /// that float shaders and this double code differ by rounding only.
    double bilinear(double u, double v) const {
        if (!(u >= -1.0 && u < 1.0 && v >= -1.0 && v < 1.0)) return 0.0;
        const double fx = (u + 1.0) * 0.5 * size - 0.5, fy = (v + 1.0) * 0.5 * size - 0.5;
        const double x0 = std::floor(fx), y0 = std::floor(fy), tx = fx - x0, ty = fy - y0;
        auto texel = [&](double x, double y) {
            const int ix = x < 0 ? 0 : (x >= size ? size - 1 : int(x));
            const int iy = y < 0 ? 0 : (y >= size ? size - 1 : int(y));
            return double(density[static_cast<std::size_t>(iy) * size + ix]);
        };
        const double top = texel(x0, y0) * (1.0 - tx) + texel(x0 + 1.0, y0) * tx;
        const double bottom = texel(x0, y0 + 1.0) * (1.0 - tx) + texel(x0 + 1.0, y0 + 1.0) * tx;
        return (top * (1.0 - ty) + bottom * ty) / 255.0;
    }
    /// Density times linear colour at (u, v), by the same bilinear rule as
    /// bilinear(): divided by bilinear(u, v), the density-weighted colour there.
    glm::dvec3 bilinearAlbedo(double u, double v) const {
        if (!(u >= -1.0 && u < 1.0 && v >= -1.0 && v < 1.0)) return glm::dvec3(0.0);
        const double fx = (u + 1.0) * 0.5 * size - 0.5, fy = (v + 1.0) * 0.5 * size - 0.5;
        const double x0 = std::floor(fx), y0 = std::floor(fy), tx = fx - x0, ty = fy - y0;
        auto texel = [&](double x, double y) {
            const int ix = x < 0 ? 0 : (x >= size ? size - 1 : int(x));
            const int iy = y < 0 ? 0 : (y >= size ? size - 1 : int(y));
            return glm::dvec3(albedo[static_cast<std::size_t>(iy) * size + ix]);
        };
        const glm::dvec3 top = texel(x0, y0) * (1.0 - tx) + texel(x0 + 1.0, y0) * tx;
        const glm::dvec3 bottom = texel(x0, y0 + 1.0) * (1.0 - tx) + texel(x0 + 1.0, y0 + 1.0) * tx;
        return top * (1.0 - ty) + bottom * ty;
    }
    /// Mean density over a footprint cell: the parallelogram centred at
    /// slice-local `c` with edges `e0`, `e1`, all in units of the yarn radius.
    /// The disk: exact coverage. A texture: bilinear at the centre.
    double footprintDensity(glm::dvec2 c, glm::dvec2 e0, glm::dvec2 e1) const {
        if (analyticDisk) return diskCoverage(c, e0, e1, 1.0);
        return bilinear(c.x, c.y);
    }
    /// Mean density over the square (fraction of the square filled by fibre).
    double meanDensity() const;
};

/// Slice-local distance from the centre, in units of the radius, beyond which
/// every lookup of `xs` reads 0: the farthest texel with fibre plus the reach
/// of the bilinear rule (a lookup reads texels within one texel of it on
/// each axis), with a margin for float rounding. A sample's footprint that
/// lies wholly beyond it has no fibre, so both backends skip it unevaluated:
/// the fibre plies fill a disk, so most of a slice's square is skipped.
/// The analytic disk: 1.
double textureSupport(const CrossSection& xs);

/// Uniform density 1 inside the unit disk; edge texels hold their coverage.
CrossSection makeDiskCrossSection(int size = 128);

/// Procedural plies of fibres like the paper's Figure 1: three plies, each a
/// bundle of small round fibres, denser towards the ply centre.
CrossSection makeFiberCrossSection(int size = 128, std::uint64_t seed = 7);

/// Loads a PNG; its alpha channel (or grey level where there is no alpha) is
/// the density. A tEXt chunk "yarn-radius" sets CrossSection::radius. With
/// `withAlbedo`, its RGB is the fibres' colour too (CrossSection::albedo):
/// sRGB-encoded 8-bit values converted to linear; throws yv::Error when the
/// PNG has no colour (every pixel with fibre has R = G = B).
CrossSection loadCrossSectionPng(const std::string& path, bool withAlbedo = false);

/// sRGB-encoded 8-bit value to linear [0, 1] (the sRGB transfer function).
double srgbToLinear(std::uint8_t value);

/// "fibers", "disk" or a path to a PNG file; `withAlbedo` (--albedo) needs a
/// colour PNG and throws yv::Error otherwise.
CrossSection makeCrossSection(const std::string& spec, bool withAlbedo = false);

} // namespace yv

// The sampling rule of formats/sampling-rule.md, for one slice, on the CPU.
#pragma once

#include "core/sampling.h"
#include "garment/cross_section.h"
#include "garment/slices.h"
#include "plan/grid.h"

#include <glm/vec3.hpp>

#include <cmath>

namespace yv {

/// One voxel's share of a sample of a slice that lands on fibre.
struct SliceSample {
    glm::ivec3 voxel;
    double volumeFraction; ///< fibre volume this share stands for / voxel volume
    float density;         ///< cross-section density at the sample, in [0, 1]
    glm::dvec3 direction;  ///< fibre direction, unit
};

/// Calls `emit(const SliceSample&)` for every voxel share of every sample of
/// `slice`: pixels of the grid's face along the slice's dominant axis,
/// `supersample`^2 per voxel face, whose square, seen on the slice plane,
/// covers some fibre (the sample's density is the footprint's mean density).
/// A sample stands for its pixel's column through the slice's slab; the
/// column is split among the voxels it crosses (a box filter in depth), one
/// share per voxel.
template <class Emit>
void sampleSlice(const Slice& slice, double radius, const CrossSection& xs, const VoxelGrid& grid, int supersample,
                 Emit&& emit) {
    const int a = dominantAxis(slice.tangent), b = (a + 1) % 3, c = (a + 2) % 3;
    const double h = grid.voxelSize, pixel = h / supersample;
    // right x up = tangent, so the 2x2 system below has determinant tangent[a].
    const double det = slice.tangent[a];
    const double Rb = slice.right[b], Rc = slice.right[c], Ub = slice.up[b], Uc = slice.up[c];

    // Pixel bounds of the slice square projected onto the (b, c) face.
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL};
    for (int corner = 0; corner < 4; ++corner) {
        const double sx = (corner & 1) ? radius : -radius, sy = (corner & 2) ? radius : -radius;
        const glm::dvec3 p = slice.center + sx * slice.right + sy * slice.up;
        const double pb = (p[b] - grid.origin[b]) / pixel, pc = (p[c] - grid.origin[c]) / pixel;
        lo[0] = std::min(lo[0], pb), hi[0] = std::max(hi[0], pb);
        lo[1] = std::min(lo[1], pc), hi[1] = std::max(hi[1], pc);
    }
    // Every pixel whose square meets the projected slice square.
    const long i0 = static_cast<long>(std::floor(lo[0])), i1 = static_cast<long>(std::ceil(hi[0])) - 1;
    const long j0 = static_cast<long>(std::floor(lo[1])), j1 = static_cast<long>(std::ceil(hi[1])) - 1;
    // The pixel's edges on the slice plane, in units of the radius.
    const glm::dvec2 edgeB = pixel / (det * radius) * glm::dvec2(Uc, -Rc);
    const glm::dvec2 edgeC = pixel / (det * radius) * glm::dvec2(-Ub, Rb);
    // Depth of the slab along the column, in voxels, before the bend's scale.
    const double depthScale = slice.thickness / (h * std::abs(det));
    const double pixelShare = 1.0 / (supersample * supersample);
    const double invRadius = 1.0 / radius;

    for (long j = j0; j <= j1; ++j) {
        const double dc = grid.origin[c] + (j + 0.5) * pixel - slice.center[c];
        for (long i = i0; i <= i1; ++i) {
            const double db = grid.origin[b] + (i + 0.5) * pixel - slice.center[b];
            const double x = (db * Uc - dc * Ub) / det;
            const double y = (Rb * dc - Rc * db) / det;
            const double coverage = xs.footprintDensity(glm::dvec2(x, y) * invRadius, edgeB, edgeC);
            if (!(coverage > 0.0)) continue;
            const double pa = slice.center[a] + x * slice.right[a] + y * slice.up[a];
            const double depth = slabScale(slice, x, y) * depthScale;
            if (!(depth > 0.0)) continue;
            const double z0 = (pa - grid.origin[a]) / h - 0.5 * depth, z1 = z0 + depth;
            SliceSample s;
            s.voxel[b] = static_cast<int>(i / supersample);
            s.voxel[c] = static_cast<int>(j / supersample);
            s.density = static_cast<float>(coverage);
            s.direction = fiberDirection(slice, x, y);
            const double weight = coverage * pixelShare;
            for (double v = std::floor(z0); v < z1; v += 1.0) {
                const double share = std::min(z1, v + 1.0) - std::max(z0, v);
                if (!(share > 0.0)) continue;
                s.voxel[a] = static_cast<int>(v);
                s.volumeFraction = weight * share;
                emit(s);
            }
        }
    }
}

} // namespace yv

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
    /// With albedo (CrossSection::hasAlbedo): the density-weighted mean linear
    /// colour of the sample's footprint cells; zero otherwise.
    glm::dvec3 albedo{0.0};
};

/// Calls `emit(const SliceSample&)` for every voxel share of every sample of
/// `slice`: pixels of the grid's face along the slice's dominant axis,
/// `supersample`^2 per voxel face, whose square, seen on the slice plane,
/// covers some fibre. A sample stands for its pixel's prism through the
/// slice's slab: its footprint on the slice is cut into cells, each with its
/// fibre coverage and its column through the slab, and every column is split
/// among the voxels it crosses (a box filter in depth); one share per voxel.
/// `support` is textureSupport(xs), computed once per run.
template <class Emit>
void sampleSlice(const Slice& slice, double radius, const CrossSection& xs, double support, const VoxelGrid& grid,
                 int supersample, Emit&& emit) {
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
    constexpr int m = CrossSection::kFootprintCells;
    const double cellShare = 1.0 / (double(supersample) * supersample * m * m);
    const double invRadius = 1.0 / radius;
    const glm::dvec2 cellB = edgeB / double(m), cellC = edgeC / double(m);
    // A footprint whose nearest point lies beyond the texture's support reads 0.
    const double reach = 0.5 * (glm::length(edgeB) + glm::length(edgeC));

    struct Cell {
        double density, z0, z1;
    };
    Cell cells[m * m];
    const bool withAlbedo = xs.hasAlbedo();
    for (long j = j0; j <= j1; ++j) {
        const double dc = grid.origin[c] + (j + 0.5) * pixel - slice.center[c];
        for (long i = i0; i <= i1; ++i) {
            const double db = grid.origin[b] + (i + 0.5) * pixel - slice.center[b];
            const double x = (db * Uc - dc * Ub) / det;
            const double y = (Rb * dc - Rc * db) / det;
            double coverage = 0.0;
            if (xs.analyticDisk) {
                coverage = xs.footprintDensity(glm::dvec2(x, y) * invRadius, edgeB, edgeC);
                if (!(coverage > 0.0)) continue;
            } else if (glm::length(glm::dvec2(x, y) * invRadius) - reach > support) {
                continue;
            }
            // The footprint in m x m cells, each with its own density and its
            // own column through the slab: the sample's volume is split in
            // depth where it actually lies, not only where its centre does.
            double zMin = HUGE_VAL, zMax = -HUGE_VAL, density = 0.0;
            glm::dvec3 weightedAlbedo(0.0);
            for (int q = 0; q < m; ++q)
                for (int p = 0; p < m; ++p) {
                    const double ob = ((p + 0.5) / m - 0.5) * pixel, oc = ((q + 0.5) / m - 0.5) * pixel;
                    const double cx = x + (ob * Uc - oc * Ub) / det, cy = y + (Rb * oc - Rc * ob) / det;
                    Cell& cell = cells[q * m + p];
                    cell.density = xs.analyticDisk && coverage >= 1.0 ? 1.0 : xs.footprintDensity(glm::dvec2(cx, cy) * invRadius, cellB, cellC);
                    const double depth = slabScale(slice, cx, cy) * depthScale;
                    const double pa = slice.center[a] + cx * slice.right[a] + cy * slice.up[a];
                    cell.z0 = (pa - grid.origin[a]) / h - 0.5 * depth;
                    cell.z1 = cell.z0 + depth;
                    if (!(cell.density > 0.0) || !(depth > 0.0)) {
                        cell.density = 0.0;
                        continue;
                    }
                    density += cell.density;
                    if (withAlbedo) weightedAlbedo += xs.bilinearAlbedo(cx * invRadius, cy * invRadius);
                    zMin = std::min(zMin, cell.z0);
                    zMax = std::max(zMax, cell.z1);
                }
            if (!(density > 0.0)) continue;
            SliceSample s;
            s.voxel[b] = static_cast<int>(i / supersample);
            s.voxel[c] = static_cast<int>(j / supersample);
            s.density = static_cast<float>(density / (m * m));
            s.direction = fiberDirection(slice, x, y);
            if (withAlbedo) s.albedo = glm::min(weightedAlbedo / density, glm::dvec3(1.0));
            // One share per voxel the cells' columns cross (a box filter in depth).
            for (double v = std::floor(zMin); v < zMax; v += 1.0) {
                double share = 0.0;
                for (const Cell& cell : cells)
                    if (cell.density > 0.0) share += cell.density * std::max(0.0, std::min(cell.z1, v + 1.0) - std::max(cell.z0, v));
                if (!(share * cellShare >= kMinVoxelShare)) continue;
                s.voxel[a] = static_cast<int>(v);
                s.volumeFraction = share * cellShare;
                emit(s);
            }
        }
    }
}

} // namespace yv

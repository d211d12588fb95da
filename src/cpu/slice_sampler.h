// The sampling rule of formats/sampling-rule.md, for one slice, on the CPU.
#pragma once

#include "core/footprint.h"
#include "core/sampling.h"
#include "garment/cross_section.h"
#include "garment/slices.h"
#include "plan/grid.h"

#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

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

/// Voxels [min, max) whose samples a caller wants (a zoom region's box): the
/// others are not emitted, and where that is known before a pixel is sampled
/// (its column outside the window across the slice's face), not computed.
/// The samples emitted are the same, bit for bit, as without a window.
struct SampleWindow {
    glm::ivec3 min{std::numeric_limits<int>::min()}, max{std::numeric_limits<int>::max()};
};

/// Pixels [lo, hi] of one face axis, cut to those whose voxel (pixel /
/// supersample, truncated as the sampler truncates) lies in [min, max). Only
/// sides with a positive bound are cut: below pixel 0 truncation sends
/// pixels -supersample+1..-1 to voxel 0.
inline void clipPixels(long& lo, long& hi, int min, int max, int supersample) {
    if (min > 0) lo = std::max(lo, long(min) * supersample);
    if (max > 0 && max != std::numeric_limits<int>::max()) hi = std::min(hi, long(max) * supersample - 1);
}

/// What sampling one slice needs that is the same for all of its pixels.
struct SliceFace {
    static constexpr int m = CrossSection::kFootprintCells;
    int a, b, c;            ///< the slice's dominant axis (the column's), and the face's two
    double h, pixel;        ///< voxel and pixel size
    double det;             ///< tangent[a]: right x up = tangent, so the 2x2 system below has this determinant
    double Rb, Rc, Ub, Uc;  ///< right and up along the face's axes
    long i0, i1, j0, j1;    ///< pixels [i0, i1] x [j0, j1] whose square meets the projected slice square
    double depthScale;      ///< the slab's depth along the column, in voxels, before the bend's scale
    double cellShare;       ///< one cell's share of a voxel's face
    double invRadius;
    FootprintShape pixelShape, cellShape; ///< the pixel's and a cell's edges on the slice plane, in radii
    double reach;           ///< half the pixel's edges (in radii): a footprint beyond the support reads 0
    double offsetX[m * m], offsetY[m * m]; ///< each cell's centre from the pixel's, on the slice plane
    double offsetReach;     ///< the largest |offset|
    double spreadA;         ///< how far the cells' centres lie from the pixel's along the column, at most
    double bend;            ///< |curvature|: the slab is at most 1 + bend |(x, y)| thick
    FiberTwist twist;
};

inline SliceFace sliceFace(const Slice& slice, double radius, const VoxelGrid& grid, int supersample) {
    constexpr int m = SliceFace::m;
    SliceFace f;
    f.a = dominantAxis(slice.tangent), f.b = (f.a + 1) % 3, f.c = (f.a + 2) % 3;
    const int a = f.a, b = f.b, c = f.c;
    f.h = grid.voxelSize, f.pixel = f.h / supersample;
    f.det = slice.tangent[a];
    f.Rb = slice.right[b], f.Rc = slice.right[c], f.Ub = slice.up[b], f.Uc = slice.up[c];

    // Pixel bounds of the slice square projected onto the (b, c) face.
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL};
    for (int corner = 0; corner < 4; ++corner) {
        const double sx = (corner & 1) ? radius : -radius, sy = (corner & 2) ? radius : -radius;
        const glm::dvec3 p = slice.center + sx * slice.right + sy * slice.up;
        const double pb = (p[b] - grid.origin[b]) / f.pixel, pc = (p[c] - grid.origin[c]) / f.pixel;
        lo[0] = std::min(lo[0], pb), hi[0] = std::max(hi[0], pb);
        lo[1] = std::min(lo[1], pc), hi[1] = std::max(hi[1], pc);
    }
    // Every pixel whose square meets the projected slice square.
    f.i0 = static_cast<long>(std::floor(lo[0])), f.i1 = static_cast<long>(std::ceil(hi[0])) - 1;
    f.j0 = static_cast<long>(std::floor(lo[1])), f.j1 = static_cast<long>(std::ceil(hi[1])) - 1;
    // The pixel's edges on the slice plane, in units of the radius.
    const glm::dvec2 edgeB = f.pixel / (f.det * radius) * glm::dvec2(f.Uc, -f.Rc);
    const glm::dvec2 edgeC = f.pixel / (f.det * radius) * glm::dvec2(-f.Ub, f.Rb);
    f.depthScale = slice.thickness / (f.h * std::abs(f.det));
    f.cellShare = 1.0 / (double(supersample) * supersample * m * m);
    f.invRadius = 1.0 / radius;
    f.pixelShape = footprintShape(edgeB, edgeC);
    f.cellShape = footprintShape(edgeB / double(m), edgeC / double(m));
    f.reach = 0.5 * (glm::length(edgeB) + glm::length(edgeC));

    double reachX = 0.0, reachY = 0.0, offsetReach2 = 0.0;
    for (int q = 0; q < m; ++q)
        for (int p = 0; p < m; ++p) {
            const double ob = ((p + 0.5) / m - 0.5) * f.pixel, oc = ((q + 0.5) / m - 0.5) * f.pixel;
            const double ox = (ob * f.Uc - oc * f.Ub) / f.det, oy = (f.Rb * oc - f.Rc * ob) / f.det;
            f.offsetX[q * m + p] = ox, f.offsetY[q * m + p] = oy;
            reachX = std::max(reachX, std::abs(ox)), reachY = std::max(reachY, std::abs(oy));
            offsetReach2 = std::max(offsetReach2, ox * ox + oy * oy);
        }
    // One square root, not a hypot a cell (libm's took 2 % of a run's time
    // where each slice is set up in several regions): the bound is used with
    // a voxel to spare.
    f.offsetReach = std::sqrt(offsetReach2);
    f.spreadA = reachX * std::abs(slice.right[a]) + reachY * std::abs(slice.up[a]);
    f.bend = glm::length(slice.curvature);
    f.twist = fiberTwist(slice);
    return f;
}

/// diskCoverage(c, shape, 1): its first tests here, where they inline (most
/// footprints lie wholly inside or outside the disk), the rest in it.
inline double diskFootprintCoverage(glm::dvec2 c, const FootprintShape& shape) {
    if (!(shape.area > 0.0)) return 0.0;
    const double dist = glm::length(c);
    if (dist - shape.reach >= 1.0) return 0.0;
    if (dist + shape.reach <= 1.0) return 1.0;
    return diskCoverage(c, shape, 1.0);
}

/// A footprint's cells that hold fibre and depth, in footprint order, each
/// with its density and its column [z0, z1) through the slab (in voxels).
struct FootprintCells {
    struct Cell {
        double density, z0, z1;
    };
    Cell cells[SliceFace::m * SliceFace::m];
    int count = 0;
    double zMin = HUGE_VAL, zMax = -HUGE_VAL, density = 0.0;
    /// Empty again, for the next pixel (the cells are not cleared: only `count` of them are read).
    void clear() { count = 0, zMin = HUGE_VAL, zMax = -HUGE_VAL, density = 0.0; }
};

/// Calls `share(v, s)` for the voxels v (whole numbers, [vLo, vHi) and
/// those the columns cross) in order: s, the cells' density times the part
/// of their column inside voxel v, summed in footprint order. Two voxels a
/// pass, so that their sums run side by side.
template <class Share>
void splitInDepth(const FootprintCells& f, double vLo, double vHi, Share&& share) {
    const double vEnd = std::min(f.zMax, vHi);
    for (double v = std::max(std::floor(f.zMin), vLo); v < vEnd; v += 2.0) {
        const double w = v + 1.0;
        double sv = 0.0, sw = 0.0;
        if (w < vEnd) {
            for (int k = 0; k < f.count; ++k) {
                const FootprintCells::Cell& cell = f.cells[k];
                sv += cell.density * std::max(0.0, std::min(cell.z1, v + 1.0) - std::max(cell.z0, v));
                sw += cell.density * std::max(0.0, std::min(cell.z1, w + 1.0) - std::max(cell.z0, w));
            }
            share(v, sv);
            share(w, sw);
        } else {
            for (int k = 0; k < f.count; ++k) {
                const FootprintCells::Cell& cell = f.cells[k];
                sv += cell.density * std::max(0.0, std::min(cell.z1, v + 1.0) - std::max(cell.z0, v));
            }
            share(v, sv);
        }
    }
}

/// Calls `emit(const SliceSample&)` for every voxel share of every sample of
/// `slice`: pixels of the grid's face along the slice's dominant axis,
/// `supersample`^2 per voxel face, whose square, seen on the slice plane,
/// covers some fibre. A sample stands for its pixel's prism through the
/// slice's slab: its footprint on the slice is cut into cells, each with its
/// fibre coverage and its column through the slab, and every column is split
/// among the voxels it crosses (a box filter in depth); one share per voxel.
/// `support` is textureSupport(xs), computed once per run.
/// With a `window`, only its voxels' shares (see SampleWindow).
template <class Emit>
void sampleSlice(const Slice& slice, double radius, const CrossSection& xs, double support, const VoxelGrid& grid,
                 int supersample, const SampleWindow& window, Emit&& emit) {
    constexpr int m = SliceFace::m;
    const SliceFace f = sliceFace(slice, radius, grid, supersample);
    const int a = f.a, b = f.b, c = f.c;
    long i0 = f.i0, i1 = f.i1, j0 = f.j0, j1 = f.j1;
    clipPixels(i0, i1, window.min[b], window.max[b], supersample);
    clipPixels(j0, j1, window.min[c], window.max[c], supersample);
    // Depth voxels of the window, as the column's loop counts them. A pixel
    // whose cells' columns all miss them is not sampled: bounds of its
    // cells' positions along the column and of their slab's depth, with a
    // voxel to spare for rounding.
    const double vLo = window.min[a], vHi = window.max[a];
    const bool depthWindow = window.min[a] != std::numeric_limits<int>::min() || window.max[a] != std::numeric_limits<int>::max();
    const bool withAlbedo = xs.hasAlbedo();
    FootprintCells cells;
    for (long j = j0; j <= j1; ++j) {
        const double dc = grid.origin[c] + (j + 0.5) * f.pixel - slice.center[c];
        for (long i = i0; i <= i1; ++i) {
            const double db = grid.origin[b] + (i + 0.5) * f.pixel - slice.center[b];
            const double x = (db * f.Uc - dc * f.Ub) / f.det;
            const double y = (f.Rb * dc - f.Rc * db) / f.det;
            if (depthWindow) {
                const double pa = (slice.center[a] + x * slice.right[a] + y * slice.up[a] - grid.origin[a]) / f.h;
                const double halfDepth = 0.5 * f.depthScale * (1.0 + f.bend * (std::sqrt(x * x + y * y) + f.offsetReach));
                const double spread = f.spreadA / f.h + halfDepth + 1.0;
                if (pa + spread <= vLo || pa - spread >= vHi) continue;
            }
            double coverage = 0.0;
            if (xs.analyticDisk) {
                coverage = diskFootprintCoverage(glm::dvec2(x, y) * f.invRadius, f.pixelShape);
                if (!(coverage > 0.0)) continue;
            } else if (glm::length(glm::dvec2(x, y) * f.invRadius) - f.reach > support) {
                continue;
            }
            // The footprint in m x m cells, each with its own density and its
            // own column through the slab: the sample's volume is split in
            // depth where it actually lies, not only where its centre does.
            cells.clear();
            glm::dvec3 weightedAlbedo(0.0);
            for (int k = 0; k < m * m; ++k) {
                const double cx = x + f.offsetX[k], cy = y + f.offsetY[k];
                const double density = !xs.analyticDisk  ? xs.bilinear(cx * f.invRadius, cy * f.invRadius)
                                       : coverage >= 1.0 ? 1.0
                                                         : diskFootprintCoverage(glm::dvec2(cx, cy) * f.invRadius, f.cellShape);
                const double depth = slabScale(slice, cx, cy) * f.depthScale;
                if (!(density > 0.0) || !(depth > 0.0)) continue;
                const double pa = slice.center[a] + cx * slice.right[a] + cy * slice.up[a];
                FootprintCells::Cell& cell = cells.cells[cells.count++];
                cell.density = density;
                cell.z0 = (pa - grid.origin[a]) / f.h - 0.5 * depth;
                cell.z1 = cell.z0 + depth;
                cells.density += density;
                if (withAlbedo) weightedAlbedo += xs.bilinearAlbedo(cx * f.invRadius, cy * f.invRadius);
                cells.zMin = std::min(cells.zMin, cell.z0);
                cells.zMax = std::max(cells.zMax, cell.z1);
            }
            if (!(cells.density > 0.0)) continue;
            SliceSample s;
            s.voxel[b] = static_cast<int>(i / supersample);
            s.voxel[c] = static_cast<int>(j / supersample);
            s.density = static_cast<float>(cells.density / (m * m));
            s.direction = fiberDirection(slice, f.twist, x, y);
            if (withAlbedo) s.albedo = glm::min(weightedAlbedo / cells.density, glm::dvec3(1.0));
            // One share per voxel the cells' columns cross (a box filter in depth).
            splitInDepth(cells, vLo, vHi, [&](double v, double share) {
                if (!(share * f.cellShare >= kMinVoxelShare)) return;
                s.voxel[a] = static_cast<int>(v);
                s.volumeFraction = share * f.cellShare;
                emit(s);
            });
        }
    }
}

/// Every share of every sample of `slice` (no window).
template <class Emit>
void sampleSlice(const Slice& slice, double radius, const CrossSection& xs, double support, const VoxelGrid& grid,
                 int supersample, Emit&& emit) {
    sampleSlice(slice, radius, xs, support, grid, supersample, SampleWindow{}, std::forward<Emit>(emit));
}

} // namespace yv

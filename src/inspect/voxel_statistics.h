// What `yarnvox inspect` says about the voxels of a volume, from a .vdb's
// leaves or a work directory's bricks alike: a density histogram, the share
// of voxels above 1, the mass, and how the orientations lie.
#pragma once

#include "core/bricks.h"

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <bit>
#include <cmath>

#include <array>
#include <cstdint>

namespace yv {

struct VoxelStatistics {
    /// Active voxels by density: ten bins of width 0.1 over (0, 1], then above 1.
    static constexpr int kBins = 11;
    std::array<std::uint64_t, kBins> histogram{};
    std::uint64_t activeVoxels = 0;
    std::uint64_t aboveOne = 0; ///< density above 1 by more than kOverOneMargin
    double densitySum = 0.0;    ///< sum of densities (times the voxel volume: the fibre volume)
    double densityMax = 0.0;
    std::uint64_t unitAxes = 0;         ///< orientations of unit length (within 1e-3)
    glm::dvec3 axisComponentSum{0.0};   ///< sum of |axis| per world axis, over unit axes

    /// Counts one active voxel. Inline: a summary calls it for every voxel
    /// of the volume (3 billion at 16384).
    void add(float density, glm::vec3 axis) {
        ++activeVoxels;
        const double d = density;
        densitySum += d;
        densityMax = std::max(densityMax, d);
        const int bin = d > 1.0 ? kBins - 1 : std::clamp(int(std::ceil(d * 10.0)) - 1, 0, kBins - 2);
        ++histogram[std::size_t(bin)];
        if (d > 1.0 + kOverOneMargin) ++aboveOne;
        // |length - 1| < 1e-3, on the squared length (no square root).
        const glm::dvec3 a(axis);
        const double squared = a.x * a.x + a.y * a.y + a.z * a.z;
        if (squared > 0.998001 && squared < 1.002001) {
            ++unitAxes;
            axisComponentSum += glm::abs(a);
        }
    }
    /// Counts the active voxels of one brick: `active` holds 8 words of its
    /// voxels, `axis` 512 axes or nullptr (a volume without orientation).
    void addBrick(const float* density, const glm::vec3* axis, const std::uint64_t* active) {
        for (int w = 0; w < kBrickVoxels / 64; ++w)
            for (std::uint64_t bits = active[w]; bits; bits &= bits - 1) {
                const int v = w * 64 + std::countr_zero(bits);
                add(density[v], axis ? axis[v] : glm::vec3(0.0f));
            }
    }
    VoxelStatistics& operator+=(const VoxelStatistics& o);
    /// Lower and upper density of bin `i` (the last bin: above 1, upper bound the largest density).
    double binLow(int i) const { return i == kBins - 1 ? 1.0 : 0.1 * i; }
    double binHigh(int i) const { return i == kBins - 1 ? densityMax : 0.1 * (i + 1); }
};

} // namespace yv

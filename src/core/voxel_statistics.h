// What `yarnvox inspect` says about the voxels of a volume, from a .vdb's
// leaves, a work directory's bricks, or the statistics the .vdb writer
// stored in the file alike: a density histogram, the share of voxels above
// 1, the mass, and how the orientations lie.
//
// The sums are exact and do not depend on the order bricks are added in:
// each brick's sum (its voxels in order) is rounded to a fixed point of
// 2^-32 and added as an integer. So counting a volume on any number of
// threads gives the same bits, and the statistics the writer stores equal
// what a later read of every voxel finds (inspect --verify compares them).
#pragma once

#include "core/bricks.h"

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <bit>
#include <cmath>

#include <array>
#include <cstdint>
#include <optional>
#include <string>

namespace yv {

/// A sum of brick sums in fixed point (2^-32), exact and order-independent;
/// a brick sum too large for it (or not finite: only other writers' files
/// have those) is kept in `outside` instead.
struct FixedPointSum {
    __extension__ using Integer = __int128;
    static constexpr double kScale = 4294967296.0; // 2^32
    Integer fixed = 0;
    double outside = 0.0;

    void add(double brickSum) {
        if (std::abs(brickSum) < 1073741824.0) // 2^30: the scaled sum fits an int64
            fixed += Integer(std::llround(brickSum * kScale));
        else
            outside += brickSum;
    }
    FixedPointSum& operator+=(const FixedPointSum& o) {
        fixed += o.fixed;
        outside += o.outside;
        return *this;
    }
    double value() const { return double(fixed) / kScale + outside; }
    bool operator==(const FixedPointSum&) const = default;
};

struct VoxelStatistics {
    /// Active voxels by density: ten bins of width 0.1 over (0, 1], then above 1.
    static constexpr int kBins = 11;
    std::array<std::uint64_t, kBins> histogram{};
    std::uint64_t activeVoxels = 0;
    std::uint64_t aboveOne = 0; ///< density above 1 by more than kOverOneMargin
    FixedPointSum densitySums;  ///< sum of densities (times the voxel volume: the fibre volume)
    float densityMax = 0.0f;
    std::uint64_t unitAxes = 0;                 ///< orientations of unit length (within 1e-3)
    std::array<FixedPointSum, 3> axisSums{};    ///< sum of |axis| per world axis, over unit axes

    double densitySum() const { return densitySums.value(); }
    glm::dvec3 axisComponentSum() const { return {axisSums[0].value(), axisSums[1].value(), axisSums[2].value()}; }

    /// Counts the active voxels of one brick: `active` holds 8 words of its
    /// voxels, `axis` 512 axes or nullptr (a volume without orientation).
    void addBrick(const float* density, const glm::vec3* axis, const std::uint64_t* active) {
        addActiveVoxels(active, axis != nullptr, [&](int v, std::size_t) { return ActiveVoxel{density[v], axis ? axis[v] : glm::vec3(0.0f)}; });
    }
    struct ActiveVoxel {
        float density;
        glm::vec3 axis;
    };
    /// The same, with each active voxel's values from `valueOf(v, k)`: voxel v,
    /// the k-th active one of the brick (so packed values need no unpacking).
    /// Inline: a summary calls it for every voxel of the volume (3 billion at 16384).
    template <typename ValueOf> void addActiveVoxels(const std::uint64_t* active, bool withAxes, ValueOf&& valueOf) {
        double brickDensity = 0.0;
        glm::dvec3 brickAxes(0.0);
        std::size_t k = 0;
        for (int w = 0; w < kBrickVoxels / 64; ++w)
            for (std::uint64_t bits = active[w]; bits; bits &= bits - 1, ++k) {
                const ActiveVoxel voxel = valueOf(w * 64 + std::countr_zero(bits), k);
                const float d = voxel.density;
                brickDensity += double(d);
                densityMax = std::max(densityMax, d);
                const int bin = d > 1.0f ? kBins - 1 : std::clamp(int(std::ceil(double(d) * 10.0)) - 1, 0, kBins - 2);
                ++histogram[std::size_t(bin)];
                if (double(d) > 1.0 + kOverOneMargin) ++aboveOne;
                if (!withAxes) continue;
                // |length - 1| < 1e-3, on the squared length (no square root).
                const glm::dvec3 a(voxel.axis);
                const double squared = a.x * a.x + a.y * a.y + a.z * a.z;
                if (squared > 0.998001 && squared < 1.002001) {
                    ++unitAxes;
                    brickAxes += glm::abs(a);
                }
            }
        activeVoxels += k;
        densitySums.add(brickDensity);
        for (int c = 0; c < 3; ++c) axisSums[std::size_t(c)].add(brickAxes[c]);
    }
    VoxelStatistics& operator+=(const VoxelStatistics& o);
    bool operator==(const VoxelStatistics&) const = default;
    /// Lower and upper density of bin `i` (the last bin: above 1, upper bound the largest density).
    double binLow(int i) const { return i == kBins - 1 ? 1.0 : 0.1 * i; }
    double binHigh(int i) const { return i == kBins - 1 ? double(densityMax) : 0.1 * (i + 1); }
};

/// The statistics as a .vdb's "yarnvox_statistics" metadata holds them, with
/// the leaves counted: one line of NAME=VALUE words, every number exact.
std::string statisticsRecord(const VoxelStatistics& s, std::uint64_t leaves);
/// Parses statisticsRecord's text; nothing when it is malformed (`why` says what).
struct RecordedStatistics {
    VoxelStatistics voxels;
    std::uint64_t leaves = 0;
};
std::optional<RecordedStatistics> parseStatisticsRecord(const std::string& text, std::string& why);

} // namespace yv

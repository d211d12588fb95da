#include "garment/radius_estimate.h"

#include "garment/catmull_rom.h"

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

namespace yv {
namespace {

/// At most this many samples: a few million distance queries take a second or two.
constexpr std::size_t kMaxSamples = std::size_t(1) << 21;
/// A piece of the same yarn counts as another strand when it lies this many
/// times farther along the yarn than in space: not a neighbour on the curve.
constexpr double kSameYarnArcFactor = 3.0;
/// Rings of grid cells searched around a sample before giving up on it.
constexpr int kMaxRings = 3;

struct Sample {
    glm::dvec3 p;
    double arc = 0.0;       ///< arc length (along the samples) from the yarn's start
    std::uint32_t yarn = 0;
    bool last = false;      ///< no piece from this sample to the next
};

using CellKey = std::uint64_t;
CellKey cellKey(glm::i64vec3 c) {
    // 21 bits per axis, wrapping: a collision only costs an extra distance test.
    return (std::uint64_t(c.x) & 0x1fffff) << 42 | (std::uint64_t(c.y) & 0x1fffff) << 21 | (std::uint64_t(c.z) & 0x1fffff);
}

double pointSegmentDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, double& along) {
    const glm::dvec3 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    along = t;
    return glm::length(p - (a + t * ab));
}

} // namespace

RadiusEstimate estimateYarnRadius(const Garment& garment) {
    RadiusEstimate result;
    const std::size_t segments = garment.segmentCount();
    if (segments == 0) return result;
    const int perSegment = static_cast<int>(std::clamp<std::size_t>(kMaxSamples / segments, 1, 4));

    // Samples along each yarn, pieces between consecutive samples.
    std::vector<Sample> samples;
    samples.reserve(segments * perSegment + garment.yarns.size());
    for (std::size_t y = 0; y < garment.yarns.size(); ++y) {
        const Yarn& yarn = garment.yarns[y];
        const std::size_t count = yarnSegmentCount(yarn, garment.curveType);
        double arc = 0.0;
        for (std::size_t s = 0; s < count; ++s) {
            const SegmentPoints sp = segmentPoints(yarn, s, garment.curveType);
            for (int k = 0; k <= perSegment; ++k) {
                if (k == perSegment && s + 1 < count) break; // the next segment's first sample
                const glm::dvec3 p = evalCatmullRom(sp, double(k) / perSegment);
                if (!samples.empty() && samples.back().yarn == y && !samples.back().last)
                    arc += glm::length(p - samples.back().p);
                samples.push_back({p, arc, static_cast<std::uint32_t>(y), false});
            }
        }
        if (!samples.empty() && samples.back().yarn == y) samples.back().last = true;
    }
    result.samples = samples.size();

    // Grid cells a few sample spacings wide: contacts lie a few spacings away.
    std::vector<double> spacing;
    for (std::size_t i = 0; i + 1 < samples.size(); i += 1 + samples.size() / 100000)
        if (!samples[i].last) spacing.push_back(glm::length(samples[i + 1].p - samples[i].p));
    if (spacing.empty()) return result;
    std::nth_element(spacing.begin(), spacing.begin() + spacing.size() / 2, spacing.end());
    const double cell = 4.0 * spacing[spacing.size() / 2];
    if (!(cell > 0.0)) return result;
    auto cellOf = [cell](const glm::dvec3& p) { return glm::i64vec3(glm::floor(p / cell)); };
    std::unordered_map<CellKey, std::vector<std::uint32_t>> grid;
    for (std::size_t i = 0; i < samples.size(); ++i)
        if (!samples[i].last) grid[cellKey(cellOf(samples[i].p))].push_back(static_cast<std::uint32_t>(i));

    // Nearest piece of another strand for every sample; pieces are no longer
    // than a cell, so one ring beyond the distance found is enough.
    std::vector<double> nearest(samples.size(), std::numeric_limits<double>::infinity());
    tbb::parallel_for(std::size_t(0), samples.size(), [&](std::size_t i) {
        const Sample& s = samples[i];
        const glm::i64vec3 c = cellOf(s.p);
        double best = std::numeric_limits<double>::infinity();
        for (int ring = 0; ring <= kMaxRings && !(best < (ring - 1) * cell); ++ring) {
            for (int dz = -ring; dz <= ring; ++dz)
                for (int dy = -ring; dy <= ring; ++dy)
                    for (int dx = -ring; dx <= ring; ++dx) {
                        if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != ring) continue;
                        const auto it = grid.find(cellKey(c + glm::i64vec3(dx, dy, dz)));
                        if (it == grid.end()) continue;
                        for (std::uint32_t j : it->second) {
                            const Sample& a = samples[j];
                            const Sample& b = samples[j + 1];
                            double along = 0.0;
                            const double d = pointSegmentDistance(s.p, a.p, b.p, along);
                            if (!(d < best)) continue;
                            if (a.yarn == s.yarn) {
                                const double arc = std::abs(a.arc + along * (b.arc - a.arc) - s.arc);
                                if (arc <= kSameYarnArcFactor * d + 2.0 * cell) continue;
                            }
                            best = d;
                        }
                    }
        }
        nearest[i] = best;
    });

    // Closest approaches along each yarn: where the distance stops falling.
    std::vector<double> contacts;
    for (std::size_t i = 0; i < samples.size(); ++i) {
        if (!std::isfinite(nearest[i])) continue;
        const bool first = i == 0 || samples[i - 1].yarn != samples[i].yarn;
        const bool last = samples[i].last;
        if ((first || nearest[i] < nearest[i - 1]) && (last || nearest[i] <= nearest[i + 1])) contacts.push_back(nearest[i]);
    }
    result.contacts = contacts.size();
    if (contacts.empty()) return result;
    std::nth_element(contacts.begin(), contacts.begin() + contacts.size() / 2, contacts.end());
    result.radius = 0.5 * contacts[contacts.size() / 2];
    return result;
}

} // namespace yv

#include "core/volume_compare.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace yv {

VolumeComparison compareVolumes(const BrickVolume& a, const BrickVolume& b, double densityTolerance) {
    std::unordered_map<std::uint64_t, const VoxelBrick*> inB;
    for (const VoxelBrick& brick : b.bricks) inB[brick.key] = &brick;
    VolumeComparison c;
    double angleSum = 0.0, weightSum = 0.0, diffSum = 0.0;
    for (const VoxelBrick& ba : a.bricks) {
        auto it = inB.find(ba.key);
        const VoxelBrick* bb = it == inB.end() ? nullptr : it->second;
        for (int v = 0; v < kBrickVoxels; ++v) {
            const bool hasA = ba.isActive(v), hasB = bb && bb->isActive(v);
            if (hasA && hasB) {
                ++c.both;
                const double diff = std::abs(double(bb->density[v]) - double(ba.density[v]));
                c.maxDensityDiff = std::max(c.maxDensityDiff, diff);
                diffSum += diff;
                c.densityWithin += diff <= densityTolerance;
                const double cosang = std::min(1.0, std::abs(double(glm::dot(ba.orientation[v], bb->orientation[v]))));
                angleSum += ba.density[v] * std::acos(cosang);
                weightSum += ba.density[v];
            } else if (hasA) {
                ++c.onlyA;
            }
        }
    }
    c.onlyB = b.activeVoxelCount() - c.both;
    const std::uint64_t either = c.both + c.onlyA + c.onlyB;
    c.iou = either ? double(c.both) / double(either) : 1.0;
    c.massRatio = a.totalMass() > 0 ? b.totalMass() / a.totalMass() : 0.0;
    c.meanAngleDeg = weightSum > 0 ? angleSum / weightSum * 180.0 / M_PI : 0.0;
    c.meanDensityDiff = c.both ? diffSum / double(c.both) : 0.0;
    return c;
}

} // namespace yv

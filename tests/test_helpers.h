// Garments and comparisons shared by the tests.
#pragma once

#include "core/bricks.h"
#include "garment/garment.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <unordered_map>

namespace yv::test {

/// A straight yarn from `start` along unit `direction`, one control point per
/// unit of length: a uniform Catmull-Rom through collinear, evenly spaced
/// points is the straight segment itself.
inline Garment straightYarn(glm::dvec3 start, glm::dvec3 direction, int length) {
    Garment g;
    Yarn y;
    for (int i = 0; i <= length; ++i) y.points.push_back(start + double(i) * glm::normalize(direction));
    g.yarns.push_back(y);
    return g;
}

/// Voxel lookup over a BrickVolume by global voxel coordinate.
class VolumeIndex {
  public:
    explicit VolumeIndex(const BrickVolume& v) : volume_(v) {
        for (std::size_t i = 0; i < v.bricks.size(); ++i) slot_[v.bricks[i].key] = i;
    }
    const VoxelBrick* brick(glm::ivec3 voxel) const {
        auto it = slot_.find(brickKey(voxel >> 3));
        return it == slot_.end() ? nullptr : &volume_.bricks[it->second];
    }
    float density(glm::ivec3 voxel) const {
        const VoxelBrick* b = brick(voxel);
        return b ? b->density[brickOffset(voxel.x & 7, voxel.y & 7, voxel.z & 7)] : 0.0f;
    }

  private:
    const BrickVolume& volume_;
    std::unordered_map<std::uint64_t, std::size_t> slot_;
};

/// Comparison of two volumes on the same grid.
struct VolumeComparison {
    double iou = 0.0;            ///< active voxels: |A and B| / |A or B|
    double massRatio = 0.0;      ///< mass(B) / mass(A)
    double meanAngleDeg = 0.0;   ///< mean axis angle over voxels active in both, density-weighted
    std::uint64_t both = 0, onlyA = 0, onlyB = 0;
};

inline VolumeComparison compareVolumes(const BrickVolume& a, const BrickVolume& b) {
    VolumeComparison c;
    VolumeIndex ib(b);
    double angleSum = 0.0, weightSum = 0.0;
    for (const VoxelBrick& ba : a.bricks) {
        const glm::ivec3 origin = brickCoord(ba.key) * 8;
        const VoxelBrick* bb = ib.brick(origin);
        for (int v = 0; v < kBrickVoxels; ++v) {
            const bool inA = ba.isActive(v), inB = bb && bb->isActive(v);
            if (inA && inB) {
                ++c.both;
                const double cosang = std::min(1.0, std::abs(double(glm::dot(ba.orientation[v], bb->orientation[v]))));
                angleSum += ba.density[v] * std::acos(cosang);
                weightSum += ba.density[v];
            } else if (inA) {
                ++c.onlyA;
            }
        }
    }
    const std::uint64_t activeB = b.activeVoxelCount();
    c.onlyB = activeB - c.both;
    c.iou = double(c.both) / double(c.both + c.onlyA + c.onlyB);
    c.massRatio = b.totalMass() / a.totalMass();
    c.meanAngleDeg = weightSum > 0 ? angleSum / weightSum * 180.0 / M_PI : 0.0;
    return c;
}

} // namespace yv::test

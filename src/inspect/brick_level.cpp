#include "inspect/brick_level.h"

#include "core/error.h"

#include <glm/common.hpp>
#include <glm/vector_relational.hpp>

#include <algorithm>
#include <unordered_map>

namespace yv {
namespace {

int floorDiv(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }
glm::ivec3 floorDiv(glm::ivec3 a, int b) { return {floorDiv(a.x, b), floorDiv(a.y, b), floorDiv(a.z, b)}; }

/// Level-0 bricks overlapping `clip`: [lo, hi) in brick coordinates.
void clipBricks(const VoxelBox& clip, glm::ivec3& lo, glm::ivec3& hi) {
    lo = floorDiv(clip.min, kBrickSize);
    hi = floorDiv(clip.max + (kBrickSize - 1), kBrickSize);
}

bool inside(glm::ivec3 c, glm::ivec3 lo, glm::ivec3 hi) {
    return !glm::any(glm::lessThan(c, lo)) && !glm::any(glm::greaterThanEqual(c, hi));
}

std::uint64_t relativeKey(glm::ivec3 c) { return brickKey(c); } // relative coordinates are never negative

} // namespace

std::uint64_t levelGpuBytes(std::uint64_t bricks, glm::ivec3 dims, int bytesPerVoxel) {
    return bricks * std::uint64_t(kBrickVoxels) * std::uint64_t(bytesPerVoxel) +
           std::uint64_t(dims.x) * std::uint64_t(dims.y) * std::uint64_t(dims.z) * 4u;
}

LevelPlan planLevel(const VolumeSource& source, const VoxelBox& clip, std::uint64_t budgetBytes, int bytesPerVoxel,
                    int maxTextureSize) {
    glm::ivec3 lo, hi;
    clipBricks(clip, lo, hi);
    std::vector<glm::ivec3> fine;
    for (const glm::ivec3& c : source.occupiedBricks())
        if (inside(c, lo, hi)) fine.push_back(c);
    std::uint64_t smallest = ~std::uint64_t(0);
    for (int level = 0; level <= 21; ++level) {
        LevelPlan p;
        p.level = level;
        p.scale = 1 << level;
        p.fineBricks = fine.size();
        const int span = kBrickSize * p.scale; // voxels per level brick
        p.originVoxel = floorDiv(lo * kBrickSize, span) * span;
        const glm::ivec3 end = floorDiv(hi * kBrickSize + (span - 1), span) * span;
        p.brickDims = glm::max((end - p.originVoxel) / span, glm::ivec3(1));
        p.bricks.reserve(fine.size());
        for (const glm::ivec3& c : fine) p.bricks.push_back(floorDiv(c * kBrickSize - p.originVoxel, span));
        std::sort(p.bricks.begin(), p.bricks.end(),
                  [](glm::ivec3 a, glm::ivec3 b) { return relativeKey(a) < relativeKey(b); });
        p.bricks.erase(std::unique(p.bricks.begin(), p.bricks.end()), p.bricks.end());
        p.gpuBytes = levelGpuBytes(p.bricks.size(), p.brickDims, bytesPerVoxel);
        smallest = std::min(smallest, p.gpuBytes);
        const int side = std::max(1, maxTextureSize / kBrickSize); // atlas bricks a side
        const bool fitsTextures = p.brickDims.x <= maxTextureSize && p.brickDims.y <= maxTextureSize &&
                                  p.brickDims.z <= maxTextureSize &&
                                  p.bricks.size() <= std::uint64_t(side) * std::uint64_t(side) * std::uint64_t(side);
        if (p.gpuBytes <= budgetBytes && fitsTextures) return p;
    }
    throw Error("the GPU budget of " + std::to_string(budgetBytes) + " bytes holds no level of this volume (the coarsest needs " +
                std::to_string(smallest) + "): raise --gpu-budget");
}

void streamLevelBricks(const VolumeSource& source, const VoxelBox& clip, const LevelPlan& plan, bool withOrientation,
                       const std::function<void(const LevelBrick&)>& visit) {
    glm::ivec3 lo, hi;
    clipBricks(clip, lo, hi);
    LevelBrick out;
    if (plan.level == 0) {
        source.forEachBrick(lo, hi, [&](const SourceBrick& b) {
            out.coord = b.coord - plan.originVoxel / kBrickSize;
            for (int x = 0; x < 8; ++x)
                for (int y = 0; y < 8; ++y)
                    for (int z = 0; z < 8; ++z) {
                        const int from = brickOffset(x, y, z), to = x + 8 * y + 64 * z;
                        out.density[std::size_t(to)] = b.density[from];
                        out.axisColour[std::size_t(to)] =
                            withOrientation && b.orientation ? glm::abs(b.orientation[from]) : glm::vec3(0.0f);
                    }
            visit(out);
        });
        return;
    }
    // Coarse: sums of density (and of density-weighted |axis|) per level voxel.
    struct Sums {
        std::array<float, 512> density{};
        std::vector<glm::vec3> axis;
    };
    std::unordered_map<std::uint64_t, Sums> sums;
    const float weight = 1.0f / float(plan.scale * plan.scale * plan.scale);
    source.forEachBrick(lo, hi, [&](const SourceBrick& b) {
        const glm::ivec3 base = b.coord * kBrickSize - plan.originVoxel;
        for (int x = 0; x < 8; ++x)
            for (int y = 0; y < 8; ++y)
                for (int z = 0; z < 8; ++z) {
                    const int from = brickOffset(x, y, z);
                    const float d = b.density[from];
                    if (d == 0.0f) continue;
                    const glm::ivec3 q = (base + glm::ivec3(x, y, z)) >> plan.level;
                    Sums& s = sums[relativeKey(q >> 3)];
                    const glm::ivec3 l = q & 7;
                    const std::size_t to = std::size_t(l.x + 8 * l.y + 64 * l.z);
                    s.density[to] += d * weight;
                    if (withOrientation && b.orientation) {
                        if (s.axis.empty()) s.axis.assign(512, glm::vec3(0.0f));
                        s.axis[to] += d * glm::abs(b.orientation[from]);
                    }
                }
    });
    for (auto& [key, s] : sums) {
        out.coord = brickCoord(key);
        for (std::size_t v = 0; v < 512; ++v) {
            out.density[v] = s.density[v];
            const float total = s.density[v] / weight;
            out.axisColour[v] = s.axis.empty() || total <= 0.0f ? glm::vec3(0.0f) : s.axis[v] / total;
        }
        visit(out);
    }
}

} // namespace yv

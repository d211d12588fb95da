#include "inspect/brick_level.h"

#include "core/error.h"

#include <glm/common.hpp>
#include <glm/vector_relational.hpp>

#include <algorithm>
#include <mutex>
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

namespace {

/// Level `level`'s plan from `bricks`, the occupied bricks of level
/// `from` <= level inside the clip box.
LevelPlan planFrom(const std::vector<glm::ivec3>& bricks, int from, int level, glm::ivec3 lo, glm::ivec3 hi,
                   int bytesPerVoxel) {
    LevelPlan p;
    p.level = level;
    p.scale = 1 << level;
    p.fineBricks = bricks.size();
    p.stored = from == level;
    const int span = kBrickSize * p.scale;          // voxels per level brick
    const int fromSpan = kBrickSize * (1 << from); // voxels per brick of `bricks`
    p.originVoxel = floorDiv(lo * fromSpan, span) * span;
    const glm::ivec3 end = floorDiv(hi * fromSpan + (span - 1), span) * span;
    p.brickDims = glm::max((end - p.originVoxel) / span, glm::ivec3(1));
    p.bricks.reserve(bricks.size());
    for (const glm::ivec3& c : bricks) p.bricks.push_back(floorDiv(c * fromSpan - p.originVoxel, span));
    std::sort(p.bricks.begin(), p.bricks.end(), [](glm::ivec3 a, glm::ivec3 b) { return relativeKey(a) < relativeKey(b); });
    p.bricks.erase(std::unique(p.bricks.begin(), p.bricks.end()), p.bricks.end());
    p.gpuBytes = levelGpuBytes(p.bricks.size(), p.brickDims, bytesPerVoxel);
    return p;
}

/// The occupied bricks of stored level `level` that overlap `clip`, and
/// their box [lo, hi) in that level's bricks.
std::vector<glm::ivec3> clippedBricks(const VolumeSource& source, int level, const VoxelBox& clip, glm::ivec3& lo,
                                      glm::ivec3& hi) {
    const int span = kBrickSize << level;
    lo = floorDiv(clip.min, span);
    hi = floorDiv(clip.max + (span - 1), span);
    std::vector<glm::ivec3> out;
    for (const glm::ivec3& c : source.occupiedLevelBricks(level))
        if (inside(c, lo, hi)) out.push_back(c);
    return out;
}

} // namespace

LevelPlan planLevel(const VolumeSource& source, const VoxelBox& clip, std::uint64_t budgetBytes, int bytesPerVoxel,
                    int maxTextureSize) {
    const int side = std::max(1, maxTextureSize / kBrickSize); // atlas bricks a side
    const auto fits = [&](const LevelPlan& p) {
        return p.gpuBytes <= budgetBytes && p.brickDims.x <= maxTextureSize && p.brickDims.y <= maxTextureSize &&
               p.brickDims.z <= maxTextureSize &&
               p.bricks.size() <= std::uint64_t(side) * std::uint64_t(side) * std::uint64_t(side);
    };
    std::uint64_t smallest = ~std::uint64_t(0);
    glm::ivec3 lo, hi;
    if (source.hasCoarseLevels()) {
        for (int level : source.storedLevels()) {
            // A level whose bricks cannot fit, whatever the clip, is not read.
            if (source.occupiedBricksAtLeast(level) * kBrickVoxels * std::uint64_t(bytesPerVoxel) > budgetBytes &&
                clip.min == source.bounds().min && clip.max == source.bounds().max)
                continue;
            const LevelPlan p = planFrom(clippedBricks(source, level, clip, lo, hi), level, level, lo, hi, bytesPerVoxel);
            smallest = std::min(smallest, p.gpuBytes);
            if (fits(p)) return p;
        }
    } else {
        const std::vector<glm::ivec3> fine = clippedBricks(source, 0, clip, lo, hi);
        for (int level = 0; level <= 21; ++level) {
            const LevelPlan p = planFrom(fine, 0, level, lo, hi, bytesPerVoxel);
            smallest = std::min(smallest, p.gpuBytes);
            if (fits(p)) return p;
        }
    }
    throw Error("the GPU budget of " + std::to_string(budgetBytes) + " bytes holds no level of this volume (the coarsest needs " +
                std::to_string(smallest) + "): raise --gpu-budget");
}

void forEachLevelZeroBrick(const VolumeSource& source, const VoxelBox& clip, const LevelPlan& plan,
                           const std::function<void(std::size_t index, const SourceBrick&)>& visit) {
    YV_CHECK(plan.level == 0);
    glm::ivec3 lo, hi;
    clipBricks(clip, lo, hi);
    const glm::ivec3 origin = plan.originVoxel / kBrickSize;
    const auto before = [](glm::ivec3 a, glm::ivec3 b) { return relativeKey(a) < relativeKey(b); };
    source.forEachBrickConcurrently(lo, hi, [&](const SourceBrick& b) {
        // plan.bricks is sorted by key: a brick's index is found where it lies.
        const glm::ivec3 c = b.coord - origin;
        const auto at = std::lower_bound(plan.bricks.begin(), plan.bricks.end(), c, before);
        YV_CHECK(at != plan.bricks.end() && *at == c);
        visit(std::size_t(at - plan.bricks.begin()), b);
    });
}

void streamLevelBricks(const VolumeSource& source, const VoxelBox& clip, const LevelPlan& plan, bool withOrientation,
                       const std::function<void(const LevelBrick&)>& visit) {
    glm::ivec3 lo, hi;
    LevelBrick out;
    if (plan.stored) {
        const int span = kBrickSize * plan.scale;
        lo = floorDiv(clip.min, span);
        hi = floorDiv(clip.max + (span - 1), span);
        source.forEachLevelBrick(plan.level, lo, hi, [&](const SourceBrick& b) {
            out.coord = b.coord - plan.originVoxel / span;
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
    clipBricks(clip, lo, hi);
    // Coarse: per plan brick a block of sums of density (and of density-
    // weighted |axis|). A level-0 brick lies inside one level brick (level
    // bricks span 8 * 2^L >= 16 voxels and are aligned), so a visit finds its
    // block once and adds its voxels there, on the source's threads; blocks
    // are locked in stripes, since above level 3 several level-0 bricks add
    // to one level voxel. The sums take about 8/6 of the GPU bytes the plan
    // fits in the budget, whatever the volume.
    const std::size_t slots = plan.bricks.size();
    std::vector<float> density(slots * kBrickVoxels, 0.0f);
    std::vector<glm::vec3> axis(withOrientation ? slots * kBrickVoxels : 0, glm::vec3(0.0f));
    std::vector<std::uint8_t> touched(slots, 0);
    std::unordered_map<std::uint64_t, std::uint32_t> slotOf;
    slotOf.reserve(slots);
    for (std::size_t i = 0; i < slots; ++i) slotOf.emplace(relativeKey(plan.bricks[i]), std::uint32_t(i));
    std::array<std::mutex, 512> stripes;
    const float weight = 1.0f / float(plan.scale * plan.scale * plan.scale);
    source.forEachBrickConcurrently(lo, hi, [&](const SourceBrick& b) {
        const glm::ivec3 base = b.coord * kBrickSize - plan.originVoxel;
        const auto found = slotOf.find(relativeKey((base >> plan.level) >> 3));
        YV_CHECK(found != slotOf.end());
        const std::size_t slot = found->second;
        float* sums = density.data() + slot * kBrickVoxels;
        glm::vec3* axisSums = withOrientation ? axis.data() + slot * kBrickVoxels : nullptr;
        // At level 0 a source brick is a level brick of its own: nothing else adds to its block.
        std::unique_lock<std::mutex> lock;
        if (plan.level > 0) lock = std::unique_lock(stripes[slot % stripes.size()]);
        for (int x = 0; x < 8; ++x)
            for (int y = 0; y < 8; ++y)
                for (int z = 0; z < 8; ++z) {
                    const int from = brickOffset(x, y, z);
                    const float d = b.density[from];
                    if (d == 0.0f) continue;
                    const glm::ivec3 l = ((base + glm::ivec3(x, y, z)) >> plan.level) & 7;
                    const std::size_t to = std::size_t(l.x + 8 * l.y + 64 * l.z);
                    sums[to] += d * weight;
                    touched[slot] = 1;
                    if (axisSums && b.orientation) axisSums[to] += d * glm::abs(b.orientation[from]);
                }
    });
    out.axisColour.fill(glm::vec3(0.0f));
    for (std::size_t i = 0; i < slots; ++i) {
        if (!touched[i]) continue;
        out.coord = plan.bricks[i];
        std::copy_n(density.data() + i * kBrickVoxels, kBrickVoxels, out.density.data());
        if (!axis.empty())
            for (std::size_t v = 0; v < std::size_t(kBrickVoxels); ++v) {
                const float total = out.density[v] / weight;
                out.axisColour[v] = total <= 0.0f ? glm::vec3(0.0f) : axis[i * kBrickVoxels + v] / total;
            }
        visit(out);
    }
}

} // namespace yv

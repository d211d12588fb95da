// Which level of detail a render can afford, and that level's bricks. Level
// 0 is the volume's own 8^3 bricks; level L's voxel is the mean of the 2^L
// cube of voxels under it, so its bricks span 8 * 2^L voxels. The coarse
// levels are computed on the host from the leaves, streamed one brick at a
// time, so only the chosen level's bricks are ever held.
#pragma once

#include "inspect/volume_source.h"

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace yv {

/// What one render streams to the GPU.
struct LevelPlan {
    int level = 0;
    int scale = 1;              ///< 2^level: voxels per level voxel along an axis
    glm::ivec3 originVoxel{0};  ///< voxel of the first level brick's corner (brick-aligned at this level)
    glm::ivec3 brickDims{0};    ///< the indirection grid: level bricks along each axis
    std::vector<glm::ivec3> bricks; ///< occupied level bricks, relative to originVoxel, sorted
    std::uint64_t gpuBytes = 0; ///< atlas and indirection texture together
    std::uint64_t fineBricks = 0; ///< occupied bricks inside the clip box of the level they are read from
    bool stored = false;          ///< read from the source's stored level, not reduced from level 0
};

/// Bytes a level needs on the GPU: `bytesPerVoxel` for each voxel of each
/// atlas brick, and 4 per cell of the indirection grid.
std::uint64_t levelGpuBytes(std::uint64_t bricks, glm::ivec3 brickDims, int bytesPerVoxel);

/// The finest level whose occupied bricks inside `clip` (voxel box), with
/// the indirection grid, fit in `budgetBytes` and whose textures stay within
/// `maxTextureSize` texels a side. A source with stored coarse levels (a
/// .vdb with a pyramid) is drawn from one of its stored levels, so a large
/// volume is never read whole; otherwise the level is reduced from level 0.
/// Throws yv::Error when no level of a 2^21-voxel grid fits (a budget below
/// a few bricks).
LevelPlan planLevel(const VolumeSource& source, const VoxelBox& clip, std::uint64_t budgetBytes, int bytesPerVoxel,
                    int maxTextureSize);

/// One brick of the chosen level, in texture order (x fastest: x + 8y + 64z).
struct LevelBrick {
    glm::ivec3 coord{0}; ///< relative to the plan's origin, in level bricks
    std::array<float, 512> density{};
    std::array<glm::vec3, 512> axisColour{}; ///< |axis|, density-weighted mean over the level voxel's cube
};

/// The bricks of a level-0 plan (`plan.level` 0, stored or not) inside
/// `clip`, each with its index in `plan.bricks`, on the source's threads:
/// `visit` is called concurrently, one call per brick.
void forEachLevelZeroBrick(const VolumeSource& source, const VoxelBox& clip, const LevelPlan& plan,
                           const std::function<void(std::size_t index, const SourceBrick&)>& visit);

/// Streams the plan's bricks to `visit`, in any order: each brick of a
/// stored level as it is read (the colour of a stored coarse level is its
/// principal axis, |axis|), or, at a level reduced from level 0, each level
/// brick once all of its voxels are summed. `withOrientation` false leaves axisColour zero.
void streamLevelBricks(const VolumeSource& source, const VoxelBox& clip, const LevelPlan& plan, bool withOrientation,
                       const std::function<void(const LevelBrick&)>& visit);

} // namespace yv

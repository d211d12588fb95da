// The bricks on the GPU that one command's pictures share. An HTML report
// draws the whole volume several times (ray cast, maximum intensity); each
// load used to read the volume again. The cache keeps the atlases it loaded,
// keyed by source, framed box, budget and colour, and hands them out again.
#pragma once

#include "inspect/brick_level.h"
#include "inspect/volume_source.h"
#include "render/brick_atlas.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace yv {

class GlContext;

/// What loading an atlas chose: the level, its bricks and bytes.
struct AtlasLoad {
    const BrickAtlas* atlas = nullptr;
    int level = 0;
    bool storedLevel = false;
    std::uint64_t fineBricks = 0, levelBricks = 0, gpuBytes = 0;
    bool fromCache = false;
};

class BrickCache {
  public:
    /// The atlas of `source` inside `box` at the finest level `budgetBytes`
    /// holds (planLevel), with orientation colours when `withOrientation`;
    /// loaded on the first request, then shared. The two most recent atlases
    /// are kept. Needs `gl` current.
    AtlasLoad load(const GlContext& gl, const VolumeSource& source, const VoxelBox& box, std::uint64_t budgetBytes,
                   bool withOrientation);

  private:
    struct Entry {
        std::uint64_t source = 0;
        VoxelBox box;
        std::uint64_t budget = 0;
        bool orientation = false;
        std::unique_ptr<BrickAtlas> atlas;
        AtlasLoad load;
    };
    std::vector<Entry> entries_; ///< most recent last
};

} // namespace yv

#include "render/brick_cache.h"

#include "core/error.h"
#include "core/trace.h"
#include "gpu/egl_context.h"

#include <algorithm>

namespace yv {
namespace {

constexpr std::size_t kKeptAtlases = 2;

bool sameBox(const VoxelBox& a, const VoxelBox& b) { return a.min == b.min && a.max == b.max; }

} // namespace

AtlasLoad BrickCache::load(const GlContext& gl, const VolumeSource& source, const VoxelBox& box,
                           std::uint64_t budgetBytes, bool withOrientation) {
    for (auto it = entries_.begin(); it != entries_.end(); ++it)
        if (it->source == source.id() && sameBox(it->box, box) && it->budget == budgetBytes &&
            it->orientation == withOrientation) {
            std::rotate(it, it + 1, entries_.end()); // now the most recent
            AtlasLoad hit = entries_.back().load;
            hit.fromCache = true;
            return hit;
        }
    const TraceSpan span("load a brick atlas");
    const LevelPlan plan = [&] {
        const TraceSpan planning("plan the atlas's level");
        return planLevel(source, box, budgetBytes, atlasBytesPerVoxel(withOrientation), gl.info().max3dTextureSize);
    }();
    if (plan.bricks.empty()) throw Error("nothing to render: no active voxel inside the framed box");
    if (entries_.size() == kKeptAtlases) entries_.erase(entries_.begin()); // its textures go before the new ones
    Entry e{source.id(), box, budgetBytes, withOrientation, nullptr, {}};
    e.atlas = std::make_unique<BrickAtlas>(plan, withOrientation, gl.info().max3dTextureSize);
    {
        const TraceSpan streaming("read and upload the level's bricks");
        // Level 0 in parallel, straight from the source's bricks; a coarser level as its bricks are summed.
        if (plan.level == 0) {
            e.atlas->uploadLevelZero(source, box);
        } else {
            streamLevelBricks(source, box, plan, withOrientation, [&](const LevelBrick& b) { e.atlas->upload(b); });
            const TraceSpan finishing("finish the atlas");
            e.atlas->finish();
        }
    }
    e.load = AtlasLoad{e.atlas.get(), plan.level, plan.stored && plan.level > 0, plan.fineBricks, plan.bricks.size(),
                       plan.gpuBytes, false};
    entries_.push_back(std::move(e));
    return entries_.back().load;
}

} // namespace yv

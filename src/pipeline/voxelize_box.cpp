#include "pipeline/voxelize_box.h"

#include "core/error.h"
#include "core/text.h"
#include "core/world_units.h"
#include "plan/zoom_plan.h"

#include <numeric>
#include <vector>

namespace yv {
namespace {

/// "x,y,z" of a world point.
std::string pointText(glm::dvec3 p) { return numberText(p.x) + "," + numberText(p.y) + "," + numberText(p.z); }

glm::dvec3 worldOf(const VoxelGrid& grid, glm::ivec3 voxel) { return grid.origin + glm::dvec3(voxel) * grid.voxelSize; }

} // namespace

std::optional<RunBox> placeRunBox(const VoxelizeJob& job, const SlicedGarment& sliced, const VoxelGrid& grid,
                                  const Tell& tell) {
    if (!job.box) return std::nullopt;
    RunBox run;
    run.placed = placeBox(*job.box, grid);
    const VoxelBox& box = run.placed.box;
    const SlicePlan& plan = sliced.plan();
    std::vector<std::uint32_t> all(plan.segments.size());
    std::iota(all.begin(), all.end(), 0u);
    for (std::uint32_t s : segmentsReaching(plan, grid, all, box.min, box.max)) {
        ++run.segments;
        run.slices += plan.segments[s].sliceCount;
        run.yarnLength += plan.segments[s].length;
    }
    const std::string where = "voxels " + run.placed.text() + " (max exclusive; world " + pointText(worldOf(grid, box.min)) +
                              " to " + pointText(worldOf(grid, box.max)) + ")";
    if (run.segments == 0) throw Error(job.box->named() + ": no yarn reaches the box, " + where + ": nothing to voxelize");
    if (job.verbose) {
        if (run.placed.clipped)
            tell("bbox: " + job.box->named() + " reaches past the grid (0,0,0 to " + std::to_string(grid.dims.x) + "," +
                 std::to_string(grid.dims.y) + "," + std::to_string(grid.dims.z) + "): clipped to it");
        tell("bbox: " + where + ", " + std::to_string(run.slices) + " of the garment's " + std::to_string(plan.sliceCount) +
             " slices reach it");
    }
    return run;
}

JsonObject boxStats(const VoxelizeJob& job, const RunBox& box, const VoxelGrid& grid) {
    const VoxelBox& b = box.placed.box;
    JsonObject out;
    out.set("asked", job.box->named())
        .set("voxels", box.placed.text())
        .set("world_min", pointText(worldOf(grid, b.min)))
        .set("world_max", pointText(worldOf(grid, b.max)))
        .set("clipped", box.placed.clipped)
        .set("segments_reaching", box.segments)
        .set("slices_reaching", box.slices);
    return out;
}

} // namespace yv

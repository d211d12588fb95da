// --lod's value (voxelize, merge): which coarse levels a .vdb gets
// (formats/vdb-subset.md, "Level of detail"). The preview pyramid, the
// default, starts at level 3, whose voxel is one level-0 brick: each brick
// gives it one record of sums, so it costs little beside level 0's leaves.
// --lod N asks for every level 1..N, each built from the one below.
#pragma once

#include "core/voxel_grid.h"

#include <string>

namespace yv {

/// The first level of the preview pyramid: one voxel per level-0 brick.
constexpr int kPreviewFirstLevel = 3;
/// The largest N `--lod N` takes (a grid's own limit, maxLodLevels, is lower).
constexpr int kMaxLodOption = 20;

/// What --lod asks for, before the grid is known.
struct LodRequest {
    enum class Kind { None, Preview, Full };
    Kind kind = Kind::Preview;
    int levels = 0; ///< Full: the coarsest level, N >= 1

    static LodRequest none() { return {Kind::None, 0}; }
    static LodRequest full(int n) { return {Kind::Full, n}; }
    bool operator==(const LodRequest&) const = default;
};

/// "preview", "0" or N, as the option is spelled.
std::string toString(const LodRequest& request);
/// "preview", "0" (none) or a whole number N in 1..kMaxLodOption (the full
/// pyramid 1..N); throws yv::Error naming the three otherwise.
LodRequest parseLodRequest(const std::string& text);

/// Levels first..last of a pyramid; none when last is 0.
struct LodLevels {
    int first = 1;
    int last = 0;
};

/// The levels `request` gives on `grid`: none; the preview's
/// kPreviewFirstLevel..maxLodLevels(grid), or none on a grid too small for
/// level 3 (it is the default: no error); or 1..N, refused beyond the grid's
/// levels (checkedLodLevels) before any work.
LodLevels lodLevelsFor(const LodRequest& request, const VoxelGrid& grid);

} // namespace yv

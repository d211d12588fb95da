// The coarser levels of --lod (lod_pyramid.h), built level by level from
// the octants each level's bricks left in the scratch file: only the
// octants' places are held in memory.
#pragma once

#include "vdb/leaf_batches.h"
#include "vdb/spill_file.h"

#include <vector>

namespace yv {

/// Builds `level` from the octants the bricks of the level below gave
/// (`octants`, sorted here by parent): each parent is its children's octants
/// put in place, then resolved and encoded; with `next`, each parent's own
/// octant for the level above goes to the scratch file and into `next`.
void buildLevel(PyramidLevel& level, SpillFile& spill, std::vector<OctantRecord>& octants,
                std::vector<OctantRecord>* next);

} // namespace yv

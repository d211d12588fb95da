// The coarser levels of --lod (lod_pyramid.h), built level by level from
// the octants each level's bricks left in the scratch file (or, for the
// preview pyramid's first level, in memory): only the octants' places are
// held in memory.
#pragma once

#include "vdb/leaf_batches.h"
#include "vdb/octant_memory.h"
#include "vdb/spill_file.h"

#include <cstdint>
#include <span>
#include <vector>

namespace yv {

/// Where the octants of the level below lie: in `memory` when given, else
/// in the scratch file.
struct OctantSource {
    const SpillFile& spill;
    const OctantMemory* memory = nullptr;

    /// Record r's bytes: where they lie in memory, else read into `buffer`.
    std::span<const std::uint8_t> bytes(const OctantRecord& r, ByteVector& buffer) const;
};

/// Builds `level` from the octants the bricks `skip` levels below gave
/// (`octants`, sorted here by parent; their bytes in `from`): each parent is
/// its children's octants put in place, then resolved and encoded; with
/// `next`, each parent's own octant for the level above goes to the scratch
/// file and into `next`.
void buildLevel(PyramidLevel& level, int skip, const OctantSource& from, std::vector<OctantRecord>& octants,
                SpillFile& spill, std::vector<OctantRecord>* next);

} // namespace yv

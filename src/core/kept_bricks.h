// A run's resolved bricks kept in memory as its regions are stored, beside
// its .vdb: what the live view draws a run from without reading the file it
// has just written back (decoding it again was most of the time from a run's
// end to its picture). Regions come from the writer's threads, concurrently;
// they are read once the run is over. Regions never share a brick
// (zoom_region.h), so a brick is kept once.
#pragma once

#include "core/bricks.h"
#include "core/packed_bricks.h"

#include <cstddef>
#include <mutex>
#include <vector>

namespace yv {

class KeptBricks {
  public:
    /// A region the GPU resolved, as it came back (copied: the writer recycles its storage).
    void add(const PackedBricks& region);
    /// A region resolved on the host (copied: the writer goes on to encode them).
    void add(const std::vector<VoxelBrick>& region);

    /// What was kept, once the run is over (no add() after these are read).
    const std::vector<PackedBricks>& packedRegions() const { return packed_; }
    const std::vector<std::vector<VoxelBrick>>& resolvedRegions() const { return resolved_; }
    /// Bricks kept, over both kinds of region.
    std::size_t brickCount() const;
    /// Host bytes held.
    std::size_t bytes() const;

  private:
    mutable std::mutex mutex_;
    std::vector<PackedBricks> packed_;
    std::vector<std::vector<VoxelBrick>> resolved_;
};

} // namespace yv

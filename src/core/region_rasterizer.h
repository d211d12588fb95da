// The interface between a backend and the pipeline: a backend rasterizes zoom
// regions one after another (the GL backend, or the CPU reference) and hands
// each finished region to a sink: a writer that puts it into the .vdb's
// leaves or into a work directory, or a test that collects it.
#pragma once

#include "core/bricks.h"
#include "core/error.h"
#include "core/packed_bricks.h"
#include "core/progress.h"
#include "core/stage_seconds.h"
#include "core/stats.h"
#include "core/zoom_region.h"

#include <string>
#include <vector>

namespace yv {

/// Receives each finished zoom region's bricks, in plan order: resolved and
/// packed (bricks with an active voxel only: the GL backend resolves on the
/// GPU), or as raw accumulators for the consumer to resolve (the CPU backend).
class RegionSink {
  public:
    virtual ~RegionSink() = default;
    /// True when the region needs no work (complete and verified in a resumed run).
    virtual bool alreadyDone(const ZoomRegion&) { return false; }
    /// Asked before each region: true ends the run there (regions already
    /// handed over stay handed over).
    virtual bool stopRequested() { return false; }
    virtual void consume(const ZoomRegion& region, PackedBricks&& bricks) = 0;
    /// A region's accumulators, sorted by key. Sinks that only ever follow
    /// the GL backend need not take them.
    virtual void consumeAccumulators(const ZoomRegion& region, std::vector<BrickAccumulator>&&) {
        throw Error("region " + std::to_string(region.id) + ": this consumer takes resolved, packed bricks only");
    }
    /// Storage for the next region's packed bricks (empty; a consumer may
    /// hand back the storage of regions it is done with, capacity kept).
    virtual PackedBricks emptyPackedBricks() { return {}; }
};

/// The region loop both backends share: `compute(region)` for each region the
/// sink still needs, in plan order, under one progress line; regions the sink
/// has already (a resumed run) are counted into `resumed`; the loop ends where
/// the sink asks it to stop (a signal), at a region boundary.
template <class Compute>
void forEachRegionToDo(const std::vector<ZoomRegion>& regions, RegionSink& sink, bool quiet, std::uint64_t& resumed,
                       Compute&& compute) {
    Progress progress("voxelize", regions.size(), quiet, "regions");
    for (const ZoomRegion& region : regions) {
        if (sink.stopRequested()) break;
        if (sink.alreadyDone(region))
            ++resumed;
        else
            compute(region);
        progress.advance(1);
    }
    progress.finish();
}

/// A backend that voxelizes the zoom regions of a plan (GlBackend, CpuRegionBackend).
class RegionRasterizer {
  public:
    virtual ~RegionRasterizer() = default;
    /// Fragments (samples) one region may produce: the zoom planner's budget.
    virtual std::uint64_t fragmentBudget() const = 0;
    /// Largest region edge in voxels.
    virtual int maxRegionSize() const = 0;
    /// The backend's work before the first region that needs no zoom plan
    /// (the GL backend's upload and programs): the pipeline plans the zoom
    /// regions meanwhile. run() does it where it was not asked for.
    virtual void prepare() {}
    /// Rasterizes `regions` in order, each handed to `sink` once finished.
    virtual void run(const std::vector<ZoomRegion>& regions, RegionSink& sink) = 0;
    /// Lets another thread destroy the backend (the pipeline frees the GPU's
    /// buffers and context while it writes the .vdb).
    virtual void releaseThread() {}

    /// What the backend counted, for --stats' "backend_stats" (its own keys;
    /// the pipeline sets "zoom_regions", "regions_computed" and
    /// "regions_resumed" to the run's totals afterwards).
    virtual JsonObject stats() const = 0;
    /// Samples that landed on fibre (the GL backend's fragments), for --stats' "samples".
    virtual std::uint64_t samples() const = 0;
    /// Parts of the voxelize stage the backend timed on its own, for the
    /// work directory's manifest ("voxelize.NAME"; none by default).
    virtual StageSeconds voxelizeParts() const { return {}; }
    /// One line on what ran, for --verbose (none by default).
    virtual std::string describe() const { return {}; }
};

} // namespace yv

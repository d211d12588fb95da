// Where a run's zoom regions go, behind one interface: straight into the
// .vdb's leaves (in memory), through a work directory that --resume can pick
// up, or through one work directory shared by the ranks of an MPI run. Each
// gives the rasterizer a sink, then the run's totals, then writes the .vdb.
#pragma once

#include "core/region_rasterizer.h"
#include "core/stage_seconds.h"
#include "core/voxel_grid.h"
#include "core/voxelize_settings.h"
#include "pipeline/cluster.h"
#include "pipeline/stage_timer.h"
#include "pipeline/voxelize_job.h"
#include "store/manifest.h"
#include "store/region_writer.h"
#include "vdb/vdb_writer.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

namespace yv {

/// What the regions came to, for the report and --stats (on rank 0 of an MPI
/// run, every rank's summed).
struct RunTotals {
    std::uint64_t regionsRasterized = 0; ///< regions rasterized and handed to the writer
    std::uint64_t regionsResumed = 0;    ///< regions found complete and verified in a resumed work dir
    std::uint64_t regionsMissing = 0;    ///< regions with no file on resume, computed
    std::uint64_t regionsDamaged = 0;    ///< region files that failed a check on resume, computed again
    std::uint64_t activeVoxels = 0, bricks = 0;
    std::uint64_t storeBytes = 0;        ///< the work dir's bytes once merged (0 in memory)
    RegionWriterStats writer;            ///< the writer's times; its tally covers the regions rasterized here
    /// The tally covers every region (none was taken from a resumed run).
    bool tallyComplete() const { return regionsResumed == 0; }
};

/// Throws the run's "no yarn reached a voxel" error when `activeVoxels` is 0.
using RefuseEmpty = std::function<void(std::uint64_t activeVoxels)>;

class RegionDestination {
  public:
    virtual ~RegionDestination() = default;
    /// The plan's regions in the order this destination takes them (plan
    /// order; the tree order of their lowest corners where the .vdb's leaves
    /// stream as they come; largest first for the ranks of an MPI run).
    virtual const std::vector<ZoomRegion>& regionOrder() const = 0;
    /// Where the rasterizer hands each finished region.
    virtual RegionSink& sink() = 0;
    /// Once the rasterizer's loop is over: waits until every region handed
    /// over is stored and returns the totals; nothing on an MPI rank other
    /// than 0, whose part of the run ends here. A signal that stopped the
    /// loop is thrown here as one line saying what was kept and how to go on.
    virtual std::optional<RunTotals> collect() = 0;
    /// Writes the .vdb from what was stored (the work dir first marked
    /// complete with `stages`) and laps "write" or "merge" on `timer`;
    /// `refuseEmpty` stops an empty volume before anything is written.
    virtual void writeVdb(VolumeMetadata& meta, RunTotals& totals, const StageSeconds& stages, StageTimer& timer,
                          const RefuseEmpty& refuseEmpty) = 0;
    /// "memory" or "work dir", for --stats' "regions_to".
    virtual const char* kind() const = 0;
};

/// What every destination is built from.
struct DestinationSetup {
    const VoxelizeJob& job;
    const std::vector<ZoomRegion>& regions; ///< the zoom plan's, in plan order
    const Tell& note;                       ///< a line to the user, from this process whatever its rank
    const VoxelGrid& grid;
    VoxelizeSettings settings;
    VdbWriteOptions writeOptions;
    StoreManifest manifest; ///< a work dir's identity (unused in memory)
    unsigned writerThreads = 2; ///< writerThreads() for the run's backend
};

/// The .vdb's leaves straight from the regions: no work dir.
std::unique_ptr<RegionDestination> makeMemoryDestination(const DestinationSetup& setup);
/// The job's work dir (default OUT.vdb.work), resumed where asked.
std::unique_ptr<RegionDestination> makeWorkDirDestination(const DestinationSetup& setup);
/// One work dir shared by the ranks of `group`, each rasterizing the regions
/// handed to it; rank 0 merges.
std::unique_ptr<RegionDestination> makeClusterDestination(const DestinationSetup& setup, Cluster& group);

/// Host memory the writer queue may hold: an eighth of physical memory, at most 4 GiB.
std::size_t writerQueueBytes();
/// Writer threads: unpacking or resolving regions and encoding their leaves
/// keep several cores busy. Of this process's share of the cores (the
/// machine's over `processesHere`, the MPI ranks on it): with
/// `hostRasterizes` (the CPU backend), whose own threads want the cores,
/// half; a GPU run's host thread mostly waits on the GPU, so all but two.
/// Two at least. YV_WRITER_THREADS=N sets the count (1 to 256; anything
/// else throws yv::Error).
unsigned writerThreads(bool hostRasterizes, int processesHere = 1);

} // namespace yv

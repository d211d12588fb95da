// Regions through a work directory: each region a verified file the moment
// it is done, so --resume computes only what is missing; the .vdb is merged
// from the files. The MPI destination (cluster_destination.cpp) shares one.
#pragma once

#include "pipeline/region_destination.h"
#include "pipeline/region_sinks.h"
#include "store/brick_store.h"

#include <memory>
#include <optional>
#include <string>

namespace yv {

class WorkDirDestination : public RegionDestination {
  public:
    /// Opens (or clears, or resumes) the job's work dir.
    explicit WorkDirDestination(const DestinationSetup& setup);

    const std::vector<ZoomRegion>& regionOrder() const override { return regions_; }
    RegionSink& sink() override { return *sink_; }
    std::optional<RunTotals> collect() override;
    void writeVdb(VolumeMetadata& meta, RunTotals& totals, const StageSeconds& stages, StageTimer& timer,
                  const RefuseEmpty& refuseEmpty) override;
    const char* kind() const override { return "work dir"; }

  protected:
    /// For the MPI destination: the store opened by its own rule; the sink set by it.
    WorkDirDestination(const DestinationSetup& setup, std::unique_ptr<BrickStore> store);
    /// This process's totals so far (no signal check).
    RunTotals localTotals();
    /// The one line for a run a signal stopped: every region so far kept in the work dir.
    std::string interruptedMessage(const std::string& signal, std::uint64_t regionsDone) const;
    /// "go on with: COMMAND": the command line, with the work dir named and --resume.
    std::string goOnWith() const;

    const VoxelizeJob& job_;
    const std::vector<ZoomRegion>& regions_; ///< in plan order
    const std::string workDir_; ///< --work-dir, or OUT.vdb.work
    VdbWriteOptions writeOptions_;
    std::unique_ptr<BrickStore> store_;
    std::optional<RegionWriter> writer_;
    std::unique_ptr<StoreSink> sink_;
};

/// The work dir a job's regions go to: --work-dir, else OUT.vdb.work.
std::string workDirOf(const VoxelizeJob& job);

} // namespace yv

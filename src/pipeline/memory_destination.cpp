// Regions straight into the .vdb's leaves: no work dir, nothing to resume.
// A run that writes no file (VoxelizeJob::bricksOnly) keeps its bricks alone.
#include "pipeline/region_destination.h"

#include "core/error.h"
#include "core/interrupt.h"
#include "core/kept_bricks.h"
#include "pipeline/region_sinks.h"
#include "vdb/merge.h"
#include "vdb/tree_order.h"

#include <optional>
#include <unordered_map>

namespace yv {
namespace {

class MemoryDestination : public RegionDestination {
  public:
    explicit MemoryDestination(const DestinationSetup& setup)
        : job_(setup.job), regions_(setup.regions),
          writer_(
              [this](std::uint64_t id, std::vector<VoxelBrick>&& resolved) {
                  if (job_.keepBricks) job_.keepBricks->add(resolved);
                  if (assembler_) assembler_->add(resolved, regionName(id));
                  regionDone(id);
              },
              [this](std::uint64_t id, const PackedBricks& packed) {
                  if (job_.keepBricks) job_.keepBricks->add(packed);
                  if (assembler_) assembler_->add(packed, regionName(id));
                  regionDone(id);
              },
              setup.settings.reduce, setup.settings.overlap, writerQueueBytes(), setup.writerThreads),
          sink_(writer_, setup.job.cancel.get()) {
        if (job_.bricksOnly()) return;
        assembler_.emplace(job_.output, setup.grid, setup.settings.reduce, setup.writeOptions);
        if (setup.writeOptions.streamLeaves) streamInTreeOrder();
    }

    const std::vector<ZoomRegion>& regionOrder() const override { return inTreeOrder_.empty() ? regions_ : inTreeOrder_; }
    RegionSink& sink() override { return sink_; }

    std::optional<RunTotals> collect() override {
        RunTotals totals;
        written_ = writer_.finish();
        for (const RegionInfo& r : written_) {
            totals.activeVoxels += r.activeVoxels;
            totals.bricks += r.brickCount;
        }
        if (interruptSignal())
            throw Error("interrupted by " + interruptSignalName() + " after " + std::to_string(sink_.consumed) + " of " +
                        std::to_string(regions_.size()) + " regions: nothing was written (" + job_.output +
                        " is untouched; a run with --work-dir DIR can be resumed)");
        totals.regionsRasterized = sink_.consumed;
        totals.writer = writer_.stats();
        return totals;
    }

    void writeVdb(VolumeMetadata& meta, RunTotals& totals, const StageSeconds&, StageTimer& timer,
                  const RefuseEmpty& refuseEmpty) override {
        meta.regions = recordedRegions(written_); // as a merge of the same regions records them
        refuseEmpty(totals.activeVoxels);
        if (!assembler_) return; // the bricks kept are the run's result
        try {
            assembler_->write(meta);
        } catch (const Interrupted&) {
            throw Interrupted("interrupted by " + interruptSignalName() +
                              " while writing the .vdb: nothing was written or kept (a run with --work-dir DIR "
                              "can be resumed); run the command again");
        }
        timer.lap("write");
    }

    const char* kind() const override { return "memory"; }

  private:
    static std::string regionName(std::uint64_t id) { return "region " + std::to_string(id); }

    /// The regions in the tree order of their lowest corners, so that the
    /// .vdb's leaves (in tree order) can be written as the regions finish:
    /// no brick of a region is before its lowest corner in that order.
    void streamInTreeOrder() {
        std::vector<ZoomRegion> order = regions_;
        std::vector<std::uint64_t> firstOrders = sortByFirstTreeOrder(order);
        if (!assembler_->streamRegions(std::move(firstOrders))) return;
        for (std::size_t i = 0; i < order.size(); ++i) positionOf_[order[i].id] = i;
        inTreeOrder_ = std::move(order);
    }

    void regionDone(std::uint64_t id) {
        if (assembler_ && !inTreeOrder_.empty()) assembler_->regionDone(positionOf_.at(id));
    }

    const VoxelizeJob& job_;
    const std::vector<ZoomRegion>& regions_;
    std::vector<ZoomRegion> inTreeOrder_; ///< where the leaves stream
    std::unordered_map<std::uint64_t, std::size_t> positionOf_; ///< a region's place in inTreeOrder_, by id
    /// Declared before the writer, whose threads add to it: they are joined first.
    std::optional<VdbAssembler> assembler_; ///< none where the run writes no file
    RegionWriter writer_;
    QueueSink sink_;
    std::vector<RegionInfo> written_; ///< what the writer put into the leaves, by region
};

} // namespace

std::unique_ptr<RegionDestination> makeMemoryDestination(const DestinationSetup& setup) {
    return std::make_unique<MemoryDestination>(setup);
}

} // namespace yv

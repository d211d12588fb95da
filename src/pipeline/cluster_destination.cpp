// The regions of one run shared by the ranks of an MPI run: every rank walks
// the same regions (largest first) and rasterizes those the hand-out gives
// it into one work dir on a file system they all see; rank 0 sums what every
// rank did and merges the .vdb.
#include "pipeline/work_dir_destination.h"

#include "core/error.h"
#include "core/interrupt.h"

#include <algorithm>
#include <filesystem>
#include <unordered_map>

namespace yv {
namespace {

/// The regions in the order they are handed out: largest first (by the
/// planner's fragment estimate), so no rank starts a big one last while the
/// others sit idle; ties in plan order.
std::vector<ZoomRegion> largestFirst(const std::vector<ZoomRegion>& regions) {
    std::vector<ZoomRegion> order = regions;
    std::stable_sort(order.begin(), order.end(), [](const ZoomRegion& a, const ZoomRegion& b) {
        return a.estimatedFragments > b.estimatedFragments;
    });
    return order;
}

/// One rank's part: a region counts as done here unless the hand-out gives
/// it to this rank (the others' regions are theirs).
class ClaimSink : public StoreSink {
  public:
    ClaimSink(BrickStore& store, RegionWriter& writer, bool resume, Cluster& cluster, const std::vector<ZoomRegion>& order)
        : StoreSink(store, writer, resume), cluster_(cluster) {
        for (std::size_t i = 0; i < order.size(); ++i) positionOf_.emplace(order[i].id, i);
        cluster_.beginHandout(order.size());
    }
    bool alreadyDone(const ZoomRegion& r) override {
        const std::uint64_t position = positionOf_.at(r.id);
        // Hand-out positions only grow, for every rank: skip ahead to this one.
        while (!exhausted_ && (!claim_ || *claim_ < position)) {
            claim_ = cluster_.claim();
            exhausted_ = !claim_;
        }
        if (exhausted_ || *claim_ != position) return true; // another rank's
        return StoreSink::alreadyDone(r);
    }

  private:
    Cluster& cluster_;
    std::unordered_map<std::uint64_t, std::uint64_t> positionOf_;
    std::optional<std::uint64_t> claim_;
    bool exhausted_ = false;
};

/// What each rank reports at the end of the hand-out, summed on rank 0.
struct RankTotals {
    bool interrupted = false;
    std::uint64_t rasterized = 0, resumed = 0, missing = 0, damaged = 0;
    ResolveTally tally;

    /// The values the cluster sums, in one fixed order (fromSums reads it back).
    std::vector<double> values() const {
        return {interrupted ? 1.0 : 0.0,  double(rasterized),         double(resumed),
                double(missing),          double(damaged),            double(tally.activeVoxels),
                double(tally.voxelsOverOne), tally.densitySum,        tally.rawDensitySum,
                tally.excessOverOne};
    }
    static RankTotals fromSums(const std::vector<double>& s) {
        const auto count = [](double v) { return static_cast<std::uint64_t>(v); };
        return {s[0] > 0.0, count(s[1]), count(s[2]), count(s[3]), count(s[4]),
                ResolveTally{count(s[5]), count(s[6]), s[7], s[8], s[9]}};
    }
};

/// Rank 0 opens (or clears, or resumes) the work dir; the others join it after.
std::unique_ptr<BrickStore> openShared(const DestinationSetup& setup, Cluster& group) {
    std::unique_ptr<BrickStore> store;
    if (group.rank() == 0) store = std::make_unique<BrickStore>(workDirOf(setup.job), setup.manifest, setup.job.resume);
    group.broadcast(0);
    if (group.rank() != 0) store = std::make_unique<BrickStore>(workDirOf(setup.job), setup.manifest, JoinStore{});
    return store;
}

class ClusterDestination : public WorkDirDestination {
  public:
    ClusterDestination(const DestinationSetup& setup, Cluster& group)
        : WorkDirDestination(setup, openShared(setup, group)), group_(group), note_(setup.note),
          order_(largestFirst(setup.regions)) {
        sink_ = std::make_unique<ClaimSink>(*store_, *writer_, job_.resume, group_, order_);
    }

    const std::vector<ZoomRegion>& regionOrder() const override { return order_; }

    std::optional<RunTotals> collect() override {
        RunTotals totals = localTotals();
        const RankTotals mine{interruptSignal() != 0, totals.regionsRasterized, totals.regionsResumed,
                              totals.regionsMissing, totals.regionsDamaged, totals.writer.tally};
        const RankTotals all = RankTotals::fromSums(group_.endHandout(mine.values()));
        if (job_.verbose && !job_.quiet)
            note_("rank " + std::to_string(group_.rank()) + ": " + std::to_string(mine.rasterized) +
                  " regions rasterized, " + std::to_string(mine.resumed) + " found done on disk");
        if (group_.rank() != 0) return std::nullopt; // rank 0 writes and reports
        if (all.interrupted) throw Error(interruptedMessage("a signal", all.rasterized + all.resumed));
        totals.regionsRasterized = all.rasterized;
        totals.regionsResumed = all.resumed;
        totals.regionsMissing = all.missing;
        totals.regionsDamaged = all.damaged;
        totals.writer.tally = all.tally;
        return totals;
    }

    void writeVdb(VolumeMetadata& meta, RunTotals& totals, const StageSeconds& stages, StageTimer& timer,
                  const RefuseEmpty& refuseEmpty) override {
        WorkDirDestination::writeVdb(meta, totals, stages, timer, refuseEmpty);
        if (job_.workDir.empty() && !job_.keepWorkDir) {
            // A default work dir served only to share the regions between the ranks.
            store_.reset();
            std::error_code ec;
            std::filesystem::remove_all(workDir_, ec);
        }
    }

  private:
    Cluster& group_;
    const Tell& note_;
    std::vector<ZoomRegion> order_;
};

} // namespace

std::unique_ptr<RegionDestination> makeClusterDestination(const DestinationSetup& setup, Cluster& group) {
    return std::make_unique<ClusterDestination>(setup, group);
}

} // namespace yv

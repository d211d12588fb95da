#include "pipeline/work_dir_destination.h"

#include "core/error.h"
#include "core/interrupt.h"
#include "vdb/merge.h"

namespace yv {

std::string workDirOf(const VoxelizeJob& job) { return job.workDir.empty() ? job.output + ".work" : job.workDir; }

WorkDirDestination::WorkDirDestination(const DestinationSetup& setup)
    : WorkDirDestination(setup, std::make_unique<BrickStore>(workDirOf(setup.job), setup.manifest, setup.job.resume)) {
    sink_ = std::make_unique<StoreSink>(*store_, *writer_, job_.resume, job_.cancel.get());
}

WorkDirDestination::WorkDirDestination(const DestinationSetup& setup, std::unique_ptr<BrickStore> store)
    : job_(setup.job), regions_(setup.regions), workDir_(workDirOf(setup.job)), writeOptions_(setup.writeOptions), store_(std::move(store)) {
    writer_.emplace(*store_, setup.settings.reduce, setup.settings.overlap, writerQueueBytes(), setup.writerThreads);
    // Said if the run must stop at once (a rank of an MPI run gone, a signal under mpirun).
    setStopNote("the regions written so far are kept in " + workDir_ + "; " + goOnWith());
}

RunTotals WorkDirDestination::localTotals() {
    writer_->finish(); // every region handed over is on disk before the run stops
    RunTotals totals;
    totals.regionsRasterized = sink_->consumed;
    totals.regionsResumed = sink_->resumed;
    totals.regionsMissing = sink_->missing;
    totals.regionsDamaged = sink_->damaged;
    totals.writer = writer_->stats();
    return totals;
}

std::string WorkDirDestination::goOnWith() const {
    const std::string& line = commandLine();
    const bool resuming = line.find(" --resume") != std::string::npos;
    // --resume needs the work dir named, also where it was the default one.
    return "go on with: " + line + (job_.workDir.empty() ? " --work-dir " + workDir_ : "") + (resuming ? "" : " --resume");
}

std::string WorkDirDestination::interruptedMessage(const std::string& signal, std::uint64_t regionsDone) const {
    return "interrupted by " + signal + " after " + std::to_string(regionsDone) + " of " +
           std::to_string(regions_.size()) + " regions, all of them kept in " + workDir_ + "; " + goOnWith();
}

std::optional<RunTotals> WorkDirDestination::collect() {
    RunTotals totals = localTotals();
    if (interruptSignal())
        throw Error(interruptedMessage(interruptSignalName(), totals.regionsRasterized + totals.regionsResumed));
    return totals;
}

void WorkDirDestination::writeVdb(VolumeMetadata& meta, RunTotals& totals, const StageSeconds& stages,
                                  StageTimer& timer, const RefuseEmpty& refuseEmpty) {
    store_->markComplete(regions_.size(), stages);
    for (const RegionInfo& r : store_->listRegions()) {
        totals.activeVoxels += r.activeVoxels;
        totals.bricks += r.brickCount;
    }
    refuseEmpty(totals.activeVoxels);
    try {
        mergeStoreToVdb(*store_, job_.output, meta, writeOptions_);
    } catch (const Interrupted&) {
        // Every region is on disk and the run marked complete: going on only merges.
        throw Interrupted("interrupted by " + interruptSignalName() + " while writing the .vdb: no .vdb was written, all " +
                          std::to_string(regions_.size()) + " regions are kept in " + workDir_ + "; " + goOnWith());
    }
    timer.lap("merge");
    totals.storeBytes = store_->bytesOnDisk();
}

std::unique_ptr<RegionDestination> makeWorkDirDestination(const DestinationSetup& setup) {
    return std::make_unique<WorkDirDestination>(setup);
}

} // namespace yv

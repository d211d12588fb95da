// Voxelize what the camera sees, off the render thread: the live view asks
// for a box and voxel size (view_region.h) when the camera stops, and a
// worker runs the same passes as `yarnvox voxelize --voxel-size V
// --bbox-world BOX` (with a GL context of its own) while frames go on being
// drawn, keeping the bricks in memory and writing no file; the render thread
// takes the finished run and swaps it into the ray cast. The worker also
// saves a run where the user asks, voxelizing it again into a .vdb, or
// through a work directory that `merge` and `inspect` read. A large run comes in two passes, a coarse one beside
// the one asked for (view_region.h's refinePass), each taken as it
// finishes (the coarse one only while no later run has been), so the view
// refines where it looks. A request for another view replaces every pass
// of an older one not yet started and gives up the passes under way once
// sliced, while planning or at their next zoom region boundary
// (VoxelizeJob::cancel: they write
// nothing, and the pages hear "dropped"), so a camera that moves on waits
// for no run of where it was. Saves are never given up.
#pragma once

#include "core/kept_bricks.h"
#include "core/voxel_grid.h"
#include "gpu/egl_context.h"
#include "pipeline/voxelize_job.h"
#include "view/view_region.h"

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace yv {

/// A finished view voxelization.
struct DetailRun {
    std::uint64_t id = 0; ///< 1, 2, ... in the order asked
    ViewVoxelization plan;
    std::shared_ptr<const KeptBricks> bricks; ///< the run's bricks: what is drawn
    VoxelGrid grid;       ///< the run's whole grid (its box is part of it)
    std::uint64_t activeVoxels = 0;
    double seconds = 0.0; ///< from the request to the bricks kept
    /// The same run from the command line, without -o: yarnvox voxelize GARMENT ...
    std::vector<std::string> command;
};

/// `job`'s options as `yarnvox voxelize` arguments: the input, then every
/// option the view passes on that differs from voxelize's default, numbers
/// in the shortest text that reads back to the same double.
std::vector<std::string> voxelizeArguments(const VoxelizeJob& job);

class ViewVoxelizer {
  public:
    /// Events for the pages, from the worker thread.
    struct Listener {
        std::function<void()> finished;                     ///< a run is ready to be taken
        std::function<void(const std::string& json)> tell;  ///< a message for every page
    };

    /// `base`: how the view voxelized its garment (input set); saves go to
    /// `saveDir`. Starts the worker.
    ViewVoxelizer(VoxelizeJob base, std::filesystem::path saveDir, Listener listener);
    /// Waits for the run under way (Ctrl-C stops it at once).
    ~ViewVoxelizer();
    ViewVoxelizer(const ViewVoxelizer&) = delete;
    ViewVoxelizer& operator=(const ViewVoxelizer&) = delete;

    /// Asks for `plan`, after `first` (its coarser pass) where given; false
    /// (nothing done) when `plan` is the run under way, waiting or last finished.
    bool request(const ViewVoxelization& plan, const std::optional<ViewVoxelization>& first = std::nullopt);
    /// The newest run finished since the last call, if any.
    std::optional<DetailRun> takeFinished();
    /// Saves finished run `run` to the save directory: voxelized again into
    /// a .vdb there, through a work directory kept beside it where `workDir`.
    void save(const DetailRun& run, bool workDir);
    /// A run under way or waiting.
    bool busy() const;

  private:
    struct Task {
        enum class Kind { Voxelize, SaveVdb, SaveWorkDir } kind = Kind::Voxelize;
        ViewVoxelization plan;
        DetailRun run; ///< what a save saves
        std::uint64_t id = 0;
        double askedAt = 0.0;
        /// A voxelize pass's: set when a newer view is asked for.
        std::shared_ptr<std::atomic<bool>> cancel;
    };
    void work();
    /// Runs a voxelize pass; a pass given up says "dropped" to the pages.
    void voxelizeOrDrop(const Task& task);
    void voxelize(const Task& task);
    void saveRun(const Task& task);
    VoxelizeJob jobFor(const ViewVoxelization& plan) const;
    /// Makes the GL contexts the final passes and the coarse ones run on,
    /// as the worker starts, so that the first stop waits for neither: none
    /// where the view voxelizes on the CPU or no context can be made (each
    /// run then makes its own attempt, and says why or takes the CPU).
    void makePassContexts();

    VoxelizeJob base_;
    std::filesystem::path saveDir_;
    Listener listener_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::vector<Task> waiting_;
    std::optional<ViewVoxelization> running_, last_;
    /// The give-up flags of the final pass under way (reset when it ends) and
    /// of the last coarse pass taken (setting a finished pass's flag does nothing).
    std::shared_ptr<std::atomic<bool>> runningCancel_, firstPassCancel_;
    std::optional<DetailRun> finished_;
    std::uint64_t nextId_ = 1;
    std::uint64_t publishedId_ = 0; ///< the newest run handed to takeFinished
    std::thread firstPass_;         ///< the coarse pass under way beside the worker, if any
    /// Kept between passes (one pass at a time on each), released from the
    /// thread of the pass that used it: coarse passes each have a thread.
    /// Set by the worker before it takes a task, read-only after.
    std::shared_ptr<GlContext> finalContext_, coarseContext_;
    bool stopping_ = false;
    std::thread worker_; ///< last: started once the rest is there
};

} // namespace yv

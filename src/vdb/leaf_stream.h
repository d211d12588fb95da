// Level 0's leaf records written into the .vdb while the run still makes
// them (vdb_writer.h, VdbAssembler::streamRegions), so that at 8192 the disk
// writes the leaves during the passes instead of after them.
//
// A grid's records must follow its topology, which needs every leaf, and
// the grids follow each other. So each of level 0's grids gets a lane far
// into the file (a sparse hole before it): its records are written there in
// tree order as soon as no region still to come can add a leaf before them,
// and at the end the topology is put just before the lane, the holes are
// cut out of the file (fallocate's COLLAPSE_RANGE, ext4 and XFS) and only a
// few zero bytes are left between a grid's descriptor and its data, where
// OpenVDB seeks by the descriptor's position (formats/vdb-subset.md).
#pragma once

#include "vdb/chunked_output.h"
#include "vdb/grid_layout.h"
#include "vdb/leaf_batches.h"
#include "vdb/spill_file.h"

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <mutex>
#include <optional>
#include <span>
#include <thread>
#include <vector>

namespace yv {

/// Where level 0's grids' records are streamed: lane g starts at laneAt[g],
/// and the holes are cut in blocks of `block` bytes.
struct StreamLanes {
    std::vector<std::uint64_t> laneAt;
    std::uint64_t block = 0;
    std::uint64_t fileBytesAtMost = 0; ///< the largest file the file system took
};

/// Lanes for `grids` grids in the empty file `fd`, or nullopt where its file
/// system cannot cut a range out of a file or hold a sparse file that large
/// (tmpfs, btrfs, NFS: the leaves are then written after the run). Leaves
/// the file empty.
std::optional<StreamLanes> planStreamLanes(int fd, int grids);

/// Cuts bytes [at, at + bytes) out of `fd` (a multiple of the lanes' block
/// each); false where the file system refuses.
bool collapseRange(int fd, std::uint64_t at, std::uint64_t bytes);

class LeafStream {
  public:
    /// `firstOrders[i]`: the least tree order key (vdb/tree_order.h) a leaf
    /// of region i can have (its lowest corner's), not decreasing with i.
    /// Records are read from `spill` and written through `output`.
    LeafStream(const SpillFile& spill, ChunkedOutput& output, int grids, StreamLanes lanes,
               std::vector<std::uint64_t> firstOrders);
    ~LeafStream();
    LeafStream(const LeafStream&) = delete;
    LeafStream& operator=(const LeafStream&) = delete;

    /// Leaves of a region not yet done, sorted by order. Thread-safe.
    /// Rethrows the stream's error (a failed write) once there is one.
    void add(std::vector<LeafRecord>&& records);
    /// Every leaf of region i is added. Thread-safe.
    void regionDone(std::size_t region);

    struct Result {
        /// Every leaf added: in tree order when `intact`; else in no order.
        /// None once finalLeaves() has handed them over.
        std::vector<LeafRecord> leaves;
        /// The records were streamed in tree order, and the lanes hold
        /// streamedBytes[g] bytes of grid g's records from their start.
        bool intact = true;
        std::uint64_t streamedBytes[kMaxGrids] = {};
        /// blockChecksum of each kChecksumBlockBytes of the lanes' bytes.
        std::vector<std::uint64_t> blockSums[kMaxGrids];
        /// Of the bytes streamed, those written while some region was not
        /// done yet: the part of the file written during the run.
        std::uint64_t bytesBeforeLastRegion = 0;
        double seconds = 0.0; ///< spent writing the steps
    };
    /// Once every region is done: every leaf, in tree order, while the
    /// stream still writes them (the writer lays out the file meanwhile).
    /// Waits for the stream's last take of leaves, which sorts them once,
    /// and hands them over: finish()'s Result then holds none. Nothing when
    /// the stream is no longer in order or has failed (finish() then says
    /// which).
    std::optional<std::vector<LeafRecord>> finalLeaves();
    /// Stops the stream's thread and hands over what it holds; rethrows its
    /// error (a failed write). Call once.
    Result finish();

  private:
    void run();
    /// Keeps the stream's first error (add() and finish() rethrow it) and wakes its waiters.
    void failed(std::exception_ptr error);
    /// Marks every pending leaf below `below` taken and returns where they
    /// lie in their batches (until the batches are erased). Under mutex_.
    std::vector<std::span<const LeafRecord>> takeBelow(std::uint64_t below);
    /// Appends leaves the frontier passed (room kept for `given` leaves, all
    /// that add() was given); returns where they start. The stream's thread's.
    std::size_t take(std::span<const std::span<const LeafRecord>> ready, std::size_t given);
    /// Consecutive bytes of one grid's records: `bytes` at `at` in its lane,
    /// read from `from` in the scratch space.
    struct SpillRun {
        std::uint64_t at, from, bytes;
    };
    /// What a step writes: its leaves' records as runs, and where each
    /// grid's records end after them.
    struct Step {
        std::vector<SpillRun> runs[kMaxGrids];
        std::uint64_t recordEnd[kMaxGrids] = {};
    };
    /// The records of the leaves taken from `first` on, after the steps before.
    Step stepFrom(std::size_t first);
    /// Writes a step's records, as far as whole blocks go (on a thread of
    /// its own, while the stream takes the next step's leaves). `early`:
    /// some region was not done yet when its leaves were taken.
    void writeStep(Step&& step, bool early);
    /// Lane bytes [at, at + out.size()) from `runs` (in lane order).
    void fillFromRuns(const std::vector<SpillRun>& runs, std::uint64_t at, std::span<std::uint8_t> out) const;

    const SpillFile& spill_;
    ChunkedOutput& output_;
    int grids_;
    StreamLanes lanes_;
    std::vector<std::uint64_t> firstOrders_;

    std::mutex mutex_;
    std::condition_variable wake_;
    /// A region's leaves, sorted; those before `taken` are streamed (taken
    /// from the front as the frontier passes them, without moving the rest).
    struct PendingBatch {
        std::vector<LeafRecord> leaves;
        std::size_t taken = 0;
    };
    std::vector<PendingBatch> pending_;
    std::vector<bool> done_;
    std::size_t nextUnfinished_ = 0; ///< regions before it are done
    std::size_t leavesGiven_ = 0;    ///< leaves add() was given
    bool stopping_ = false;
    bool abandoned_ = false; ///< the run is given up: stream nothing more

    // The stream's thread's own; result_'s streamed bytes, block sums and
    // seconds the writing step's (one at a time, after the step before).
    std::uint64_t streamedBelow_ = 0; ///< every leaf below this order is taken (or being taken)
    Result result_;
    std::uint64_t recordBytes_[kMaxGrids] = {}; ///< records of result_.leaves, per grid
    /// The writing step's: runs from the last block it cut on, per grid.
    std::vector<SpillRun> runs_[kMaxGrids];
    std::exception_ptr error_; ///< set under mutex_
    bool leavesFinal_ = false; ///< the last take is in, and the stream reads its leaves no more (under mutex_)
    bool handedOver_ = false;  ///< finalLeaves() took the leaves
    std::thread thread_;
};

} // namespace yv

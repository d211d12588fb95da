// The pipeline stage between the voxelizer and the disk: takes finished
// regions (raw accumulators to resolve, or bricks the GPU already resolved,
// packed), unpacks or resolves, compresses and writes them on worker threads,
// and bounds the memory held by regions waiting their turn.
#pragma once

#include "core/bricks.h"
#include "core/packed_bricks.h"
#include "store/brick_store.h"

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace yv {

struct RegionWriterStats {
    double resolveSeconds = 0.0;    ///< resolving accumulators, unpacking resolved bricks, or (packed destination) their tallies; summed over workers
    double encodeSeconds = 0.0;     ///< serialise, compress, checksum; summed over workers
    double writeSeconds = 0.0;      ///< write, fsync, rename; summed over workers
    double submitWaitSeconds = 0.0; ///< time submit() blocked on a full queue (the producer stalled on disk)
    std::uint64_t regionsWritten = 0, bricksWritten = 0, bytesWritten = 0;
    std::uint64_t peakQueuedBytes = 0; ///< most region bytes (accumulators or packed bricks) held at once, queued or in a worker
    ResolveTally tally;                ///< over the regions written, summed in region id order
};

class RegionWriter {
  public:
    /// Starts `workers` threads (0: two, so one region's disk write overlaps
    /// the next one's compression) writing into `store`, whose reduce mode must
    /// be `reduce`; accumulators resolve with `overlap`. At most
    /// `maxQueuedBytes` of accumulators or packed bricks are held at once,
    /// counting regions queued and regions being worked on.
    RegionWriter(BrickStore& store, Reduce reduce, Overlap overlap, std::size_t maxQueuedBytes, unsigned workers = 0);
    /// Where resolved regions go when there is no store (called on worker threads, concurrently).
    using Destination = std::function<void(std::uint64_t id, std::vector<VoxelBrick>&& bricks)>;
    /// The same pipeline, handing each resolved region to `destination`
    /// instead of writing it (RegionInfo of such regions has no file).
    RegionWriter(Destination destination, Reduce reduce, Overlap overlap, std::size_t maxQueuedBytes,
                 unsigned workers = 0);
    /// Where regions the GPU resolved go as they came back, packed (called on
    /// worker threads, concurrently): no VoxelBrick is filled for them.
    using PackedDestination = std::function<void(std::uint64_t id, const PackedBricks& bricks)>;
    /// As above, with the GPU's resolved regions to `packedDestination`;
    /// regions of accumulators are resolved and go to `destination`.
    RegionWriter(Destination destination, PackedDestination packedDestination, Reduce reduce, Overlap overlap,
                 std::size_t maxQueuedBytes, unsigned workers = 0);
    /// Stops the workers after the regions they hold; regions still queued are
    /// dropped (call finish() to write everything).
    ~RegionWriter();
    RegionWriter(const RegionWriter&) = delete;
    RegionWriter& operator=(const RegionWriter&) = delete;

    /// Queues one region's accumulators (any order; bricks that resolve to no
    /// active voxel are dropped, a region may end up with none). Blocks while
    /// the bound would be exceeded, unless nothing is held (a region larger than
    /// the bound is taken alone). Throws the first worker error once one occurred.
    void submit(std::uint64_t id, glm::ivec3 min, glm::ivec3 max, std::vector<BrickAccumulator> accumulators);
    /// Queues one region whose bricks are already resolved (the GPU resolve's
    /// packed readback), under the same bound; the workers unpack them, sum
    /// their tallies in header order, and write them as submit() does. A
    /// header that contradicts the voxels is a worker error.
    void submitResolved(std::uint64_t id, glm::ivec3 min, glm::ivec3 max, PackedBricks bricks);
    /// Empty packed-brick storage for the next region, recycled from one the
    /// workers finished unpacking (capacity kept), else new. A region's
    /// readback then lands in memory already paged in: fresh pages cost more
    /// than the copy itself (1.3 of 1.7 s of readback on the H100, sweater at 4096).
    PackedBricks recycledPackedBricks();
    /// Waits for every submitted region, then returns them sorted by id, or
    /// rethrows the first worker error.
    std::vector<RegionInfo> finish();
    /// Counters so far (complete after finish()).
    RegionWriterStats stats() const;

  private:
    struct Job {
        std::uint64_t id = 0;
        glm::ivec3 min{0}, max{0};
        std::vector<BrickAccumulator> accumulators;
        PackedBricks resolved; ///< used when `isResolved`
        bool isResolved = false;
        std::size_t bytes = 0;
    };
    void start(unsigned workers);
    void enqueue(Job job);
    /// The job's bricks, resolved or unpacked, and their tally.
    std::vector<VoxelBrick> bricksOf(Job& job, ResolveTally& tally);
    /// Keeps `bricks`' storage for recycledPackedBricks(), up to kSpareStorage of them.
    void recycle(PackedBricks&& bricks);
    void work();
    void process(Job& job);
    void stop();

    BrickStore* store_ = nullptr;
    Destination destination_;
    PackedDestination packedDestination_;
    Reduce reduce_;
    Overlap overlap_;
    std::size_t maxQueuedBytes_;

    mutable std::mutex mutex_;
    std::condition_variable workReady_, spaceFree_;
    std::deque<Job> queue_;
    std::size_t heldBytes_ = 0;
    bool closing_ = false;
    std::exception_ptr error_;
    std::vector<RegionInfo> results_;
    /// Packed-brick storage the workers are done with, for the next regions:
    /// at most kSpareStorage, each within a kSpareStorage-th of the queue's
    /// bound or of 64 MiB, whichever is more (the bound does not count them:
    /// they hold no region).
    static constexpr std::size_t kSpareStorage = 4;
    std::vector<PackedBricks> spareStorage_;
    RegionWriterStats stats_;  ///< but its tally: stats() sums regionTallies_
    std::vector<std::pair<std::uint64_t, ResolveTally>> regionTallies_; ///< per region written, by id
    std::vector<std::thread> threads_;
};

} // namespace yv

// The sinks the destinations give the rasterizer: each hands finished
// regions to a RegionWriter and counts what it was given.
#pragma once

#include "core/interrupt.h"
#include "core/region_rasterizer.h"
#include "store/brick_store.h"
#include "store/region_writer.h"

#include <atomic>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace yv {

/// Hands finished regions to the RegionWriter, which resolves or unpacks them
/// on its threads and puts them into the .vdb's leaves or a work directory.
class QueueSink : public RegionSink {
  public:
    /// `cancel`: where set, the run may be given up (VoxelizeJob::cancel).
    explicit QueueSink(RegionWriter& writer, const std::atomic<bool>* cancel = nullptr)
        : writer_(writer), cancel_(cancel) {}
    void consume(const ZoomRegion& r, PackedBricks&& bricks) override {
        writer_.submitResolved(r.id, r.min, r.max, std::move(bricks));
        ++consumed;
    }
    void consumeAccumulators(const ZoomRegion& r, std::vector<BrickAccumulator>&& accumulators) override {
        writer_.submit(r.id, r.min, r.max, std::move(accumulators));
        ++consumed;
    }
    PackedBricks emptyPackedBricks() override { return writer_.recycledPackedBricks(); }
    /// SIGINT or SIGTERM, or the run given up: stop at this region boundary.
    bool stopRequested() override { return interruptSignal() != 0 || (cancel_ && cancel_->load()); }
    std::uint64_t consumed = 0; ///< regions handed to the writer

  private:
    RegionWriter& writer_;
    const std::atomic<bool>* cancel_;
};

/// Feeds a work directory; on --resume, skips regions whose files are
/// complete and verified.
class StoreSink : public QueueSink {
  public:
    StoreSink(BrickStore& store, RegionWriter& writer, bool resume, const std::atomic<bool>* cancel = nullptr)
        : QueueSink(writer, cancel), store_(store), resume_(resume) {}
    bool alreadyDone(const ZoomRegion& r) override {
        if (!resume_) return false;
        switch (store_.verifyRegion(r.id, r.min, r.max)) {
        case BrickStore::RegionState::Verified: ++resumed; return true;
        case BrickStore::RegionState::Missing: ++missing; return false;
        case BrickStore::RegionState::Damaged: ++damaged; return false;
        }
        return false;
    }
    std::uint64_t resumed = 0; ///< regions found complete and verified
    std::uint64_t missing = 0; ///< regions with no file on resume (the run stopped before them): computed
    std::uint64_t damaged = 0; ///< region files that failed a check on resume, deleted: computed again

  private:
    BrickStore& store_;
    bool resume_;
};

} // namespace yv

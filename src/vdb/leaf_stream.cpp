#include "vdb/leaf_stream.h"

#include "core/error.h"
#include "core/interrupt.h"
#include "core/trace.h"
#include "vdb/grid_checksums.h"

#include <fcntl.h>
#include <linux/falloc.h>
#include <sys/stat.h>
#include <sys/vfs.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <future>
#include <limits>
#include <optional>
#include <span>

namespace yv {
namespace {

/// Lanes this far apart: no grid's records come near it (an 8192 run's
/// orientation grid takes about 10 GB), and 3 grids' lanes fit ext4's 16 TiB
/// files. A file system with a smaller limit gets lanes a quarter as far
/// apart, down to kLeastLaneSpacing.
constexpr std::uint64_t kLaneSpacing = 1ull << 40;
constexpr std::uint64_t kLeastLaneSpacing = 1ull << 34;

constexpr std::uint64_t kNoRegionLeft = std::numeric_limits<std::uint64_t>::max();

/// Threads of the stream's own writing its chunks: a few writes in flight
/// keep the disk's queue full. TBB's would wait behind the regions'
/// encoding, which keeps every worker busy at 8192: there the stream
/// wrote at the speed of one chunk at a time.
constexpr int kStreamWriters = 4;

/// Whether `next` (sorted) goes on after `leaves` in tree order: every leaf
/// past the last of `leaves`, and no two of `next` the same brick.
bool followsInOrder(std::span<const LeafRecord> leaves, std::span<const LeafRecord> next) {
    bool ordered = next.empty() || leaves.empty() || next.front().order > leaves.back().order;
    for (std::size_t i = 1; ordered && i < next.size(); ++i) ordered = next[i].order != next[i - 1].order;
    return ordered;
}

} // namespace

bool collapseRange(int fd, std::uint64_t at, std::uint64_t bytes) {
    return ::fallocate(fd, FALLOC_FL_COLLAPSE_RANGE, off_t(at), off_t(bytes)) == 0;
}

std::optional<StreamLanes> planStreamLanes(int fd, int grids) {
    struct statfs fs {};
    if (::fstatfs(fd, &fs) != 0) return std::nullopt;
    StreamLanes lanes;
    lanes.block = std::max<std::uint64_t>(ChunkedOutput::kAlignment, std::uint64_t(fs.f_bsize));
    if (lanes.block % ChunkedOutput::kAlignment != 0 || kLeastLaneSpacing % lanes.block != 0) return std::nullopt;
    // A block cut out of three: what the end of the run does, on a file that holds nothing yet.
    struct stat st {};
    bool usable = ::ftruncate(fd, off_t(3 * lanes.block)) == 0 && collapseRange(fd, lanes.block, lanes.block) &&
                  ::fstat(fd, &st) == 0 && std::uint64_t(st.st_size) == 2 * lanes.block;
    std::uint64_t spacing = kLaneSpacing;
    while (usable && ::ftruncate(fd, off_t(std::uint64_t(grids + 1) * spacing)) != 0) {
        spacing /= 4;
        usable = spacing >= kLeastLaneSpacing;
    }
    if (::ftruncate(fd, 0) != 0 || !usable) return std::nullopt;
    for (int g = 0; g < grids; ++g) lanes.laneAt.push_back(std::uint64_t(g + 1) * spacing);
    lanes.fileBytesAtMost = std::uint64_t(grids + 1) * spacing;
    return lanes;
}

LeafStream::LeafStream(const SpillFile& spill, ChunkedOutput& output, int grids, StreamLanes lanes,
                       std::vector<std::uint64_t> firstOrders)
    : spill_(spill), output_(output), grids_(grids), lanes_(std::move(lanes)), firstOrders_(std::move(firstOrders)),
      done_(firstOrders_.size(), false) {
    YV_CHECK(grids_ >= 1 && grids_ <= kMaxGrids && int(lanes_.laneAt.size()) == grids_);
    YV_CHECK(std::is_sorted(firstOrders_.begin(), firstOrders_.end()));
    thread_ = std::thread([this] { run(); });
}

LeafStream::~LeafStream() {
    if (!thread_.joinable()) return;
    {
        std::lock_guard lock(mutex_);
        stopping_ = abandoned_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

void LeafStream::add(std::vector<LeafRecord>&& records) {
    std::lock_guard lock(mutex_);
    // A failed write (a full disk) stops the run at its next region, not after the last.
    if (error_) std::rethrow_exception(error_);
    if (records.empty()) return;
    leavesGiven_ += records.size();
    pending_.push_back({std::move(records), 0});
}

void LeafStream::regionDone(std::size_t region) {
    {
        std::lock_guard lock(mutex_);
        YV_CHECK(region < done_.size() && !done_[region]);
        done_[region] = true;
        while (nextUnfinished_ < done_.size() && done_[nextUnfinished_]) ++nextUnfinished_;
    }
    wake_.notify_all();
}

void LeafStream::run() {
    // A step's records are written on a thread of their own while this one
    // takes the next step's leaves: the take (a sort of up to a million
    // leaves at 8192) no longer leaves the disk idle. Steps still write one
    // after another, in order.
    std::future<void> writing;
    try {
        for (;;) {
            std::vector<std::span<const LeafRecord>> ready;
            std::uint64_t below = 0;
            std::size_t given = 0;
            {
                std::unique_lock lock(mutex_);
                // Leaves below the frontier are final: every region that could add one is done.
                const auto frontier = [&] {
                    return nextUnfinished_ < firstOrders_.size() ? firstOrders_[nextUnfinished_] : kNoRegionLeft;
                };
                wake_.wait(lock, [&] { return stopping_ || error_ || frontier() > streamedBelow_; });
                below = frontier();
                if (abandoned_ || error_ || below <= streamedBelow_) break; // stopping, and nothing new
                streamedBelow_ = below;
                ready = takeBelow(below);
                given = leavesGiven_;
            }
            // Outside the lock, so that add() is never held up by a take: the
            // batches' leaves stay where they lie (add() appends batches, and
            // moving a batch keeps its leaves' storage), and only this thread
            // erases batches.
            const std::size_t first = take(ready, given);
            const bool early = below != kNoRegionLeft;
            std::optional<Step> step;
            if (result_.intact && first < result_.leaves.size()) step = stepFrom(first);
            {
                std::lock_guard lock(mutex_);
                std::erase_if(pending_, [](const PendingBatch& b) { return b.taken == b.leaves.size(); });
                // The last step no longer reads the leaves: finalLeaves() may take them.
                leavesFinal_ = !early;
            }
            wake_.notify_all();
            if (!step) continue;
            if (writing.valid()) writing.wait(); // one step written at a time, in order
            writing = std::async(std::launch::async, [this, early, next = std::move(*step)]() mutable {
                try {
                    writeStep(std::move(next), early);
                } catch (...) {
                    failed(std::current_exception()); // a full disk stops the run at its next region
                }
            });
        }
    } catch (...) {
        failed(std::current_exception());
    }
    if (writing.valid()) writing.wait();
}

void LeafStream::failed(std::exception_ptr error) {
    {
        std::lock_guard lock(mutex_);
        if (!error_) error_ = std::move(error);
    }
    wake_.notify_all();
}

std::vector<std::span<const LeafRecord>> LeafStream::takeBelow(std::uint64_t below) {
    std::vector<std::span<const LeafRecord>> ready;
    for (PendingBatch& batch : pending_) {
        const auto from = batch.leaves.begin() + std::ptrdiff_t(batch.taken);
        const auto cut =
            std::partition_point(from, batch.leaves.end(), [&](const LeafRecord& r) { return r.order < below; });
        if (cut != from) ready.emplace_back(from, cut);
        batch.taken = std::size_t(cut - batch.leaves.begin());
    }
    return ready;
}

/// Appends `ready` (every leaf between the last frontier and this one) to
/// the leaves taken, in tree order; returns where it starts.
std::size_t LeafStream::take(std::span<const std::span<const LeafRecord>> ready, std::size_t given) {
    std::vector<LeafRecord>& leaves = result_.leaves;
    const std::size_t first = leaves.size();
    if (ready.empty()) return first;
    const TraceSpan span("take the leaves the frontier passed");
    std::size_t count = 0;
    for (std::span<const LeafRecord> piece : ready) count += piece.size();
    // Room for every leaf given so far: the last take (half the leaves of the
    // draped garment at 8192) then rarely moves the ones taken before.
    if (leaves.capacity() < first + count) leaves.reserve(std::max(given, 2 * leaves.capacity()));
    appendInTreeOrder(ready, leaves);
    // A leaf at or below one already streamed (a brick given twice, or out
    // of its region): the stream stops, and the end writes the file whole.
    const std::span<const LeafRecord> all(leaves);
    result_.intact = result_.intact && followsInOrder(all.first(first), all.subspan(first));
    return first;
}

std::optional<std::vector<LeafRecord>> LeafStream::finalLeaves() {
    std::unique_lock lock(mutex_);
    YV_CHECK(nextUnfinished_ == done_.size());
    // Every region is done, so the stream's next take is its last: every
    // leaf, sorted once there. Once the stream has found where their records
    // lie, it no longer reads them: they are handed over, not copied.
    wake_.wait(lock, [&] { return leavesFinal_ || error_ || abandoned_; });
    if (error_ || abandoned_ || !result_.intact) return std::nullopt;
    YV_CHECK(pending_.empty());
    handedOver_ = true;
    return std::move(result_.leaves);
}

/// Where the records of the leaves taken from `first` on lie in the scratch
/// space, after those of the steps before, for each grid.
LeafStream::Step LeafStream::stepFrom(std::size_t first) {
    signalAtTestPoint("stream-leaves"); // a signal while the regions still come
    const std::vector<LeafRecord>& leaves = result_.leaves;
    Step step;
    for (int g = 0; g < grids_; ++g) {
        std::vector<SpillRun>& runs = step.runs[g];
        std::uint64_t& at = recordBytes_[g];
        for (std::size_t i = first; i < leaves.size(); ++i) {
            const std::uint64_t from = leaves[i].at[g], bytes = leaves[i].bytes[g];
            if (bytes == 0) continue;
            if (!runs.empty() && runs.back().from + runs.back().bytes == from) runs.back().bytes += bytes;
            else runs.push_back({at, from, bytes});
            at += bytes;
        }
        step.recordEnd[g] = at;
    }
    return step;
}

/// Fills out[0, n) with lane bytes [at, at + n) from `runs` (in lane order).
void LeafStream::fillFromRuns(const std::vector<SpillRun>& runs, std::uint64_t at, std::span<std::uint8_t> out) const {
    const std::uint64_t end = at + out.size();
    auto run = std::partition_point(runs.begin(), runs.end(), [&](const SpillRun& r) { return r.at + r.bytes <= at; });
    for (; run != runs.end() && run->at < end; ++run) {
        const std::uint64_t lo = std::max(run->at, at), hi = std::min(run->at + run->bytes, end);
        spill_.read(run->from + (lo - run->at), out.subspan(lo - at, hi - lo));
    }
}

/// Writes each grid's records as far as whole blocks go: a block cut by the
/// last record is written again, whole, next time. `early`: some region was
/// not done yet when the leaves were taken.
void LeafStream::writeStep(Step&& step, bool early) {
    const TraceSpan span("stream leaf records");
    const auto start = std::chrono::steady_clock::now();
    constexpr std::uint64_t kBlock = kChecksumBlockBytes;
    static_assert(kBlock % ChunkedOutput::kAlignment == 0);
    for (int g = 0; g < grids_; ++g) {
        std::vector<SpillRun>& runs = runs_[g];
        runs.insert(runs.end(), step.runs[g].begin(), step.runs[g].end());
        const std::uint64_t from = result_.streamedBytes[g], to = step.recordEnd[g] / kBlock * kBlock;
        if (to <= from) continue;
        std::vector<std::uint64_t>& sums = result_.blockSums[g];
        sums.resize(to / kBlock);
        const std::uint64_t lane = lanes_.laneAt[g];
        output_.writeRangeOnThreads(lane + from, lane + to, [&](std::uint64_t at, std::span<std::uint8_t> out) {
            fillFromRuns(runs, at - lane, out);
            for (std::uint64_t b = 0; b < out.size(); b += kBlock)
                sums[(at - lane + b) / kBlock] = blockChecksum(out.subspan(b, kBlock));
        }, kStreamWriters);
        result_.streamedBytes[g] = to;
        if (early) result_.bytesBeforeLastRegion += to - from;
        // Only the block cut by the last record is written again.
        std::erase_if(runs, [&](const SpillRun& r) { return r.at + r.bytes <= to; });
    }
    result_.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

LeafStream::Result LeafStream::finish() {
    const TraceSpan span("wait for the leaf stream");
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    thread_.join();
    if (error_) std::rethrow_exception(error_);
    // What no frontier passed: the last regions' leaves (or every leaf of a run given up early).
    if (!handedOver_) take(takeBelow(kNoRegionLeft), leavesGiven_);
    pending_.clear();
    return std::move(result_);
}

} // namespace yv

#include "store/region_writer.h"

#include "core/error.h"
#include "core/trace.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>

namespace yv {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::size_t heldBytes(const std::vector<BrickAccumulator>& accumulators) {
    std::size_t n = accumulators.capacity() * sizeof(BrickAccumulator);
    for (const BrickAccumulator& a : accumulators) n += a.words.capacity() * sizeof(std::uint32_t);
    return n;
}

} // namespace

RegionWriter::RegionWriter(BrickStore& store, Reduce reduce, Overlap overlap, std::size_t maxQueuedBytes,
                           unsigned workers)
    : store_(&store), reduce_(reduce), overlap_(overlap), maxQueuedBytes_(maxQueuedBytes) {
    if (store.manifest().reduce != reduce)
        throw Error(store.dir() + ": the work dir holds " + toString(store.manifest().reduce) +
                    " bricks, the writer was asked for " + toString(reduce));
    if (store.readOnly()) throw Error(store.dir() + ": cannot write regions: the work dir was opened read-only");
    start(workers);
}

RegionWriter::RegionWriter(Destination destination, Reduce reduce, Overlap overlap, std::size_t maxQueuedBytes,
                           unsigned workers)
    : RegionWriter(std::move(destination), nullptr, reduce, overlap, maxQueuedBytes, workers) {}

RegionWriter::RegionWriter(Destination destination, PackedDestination packedDestination, Reduce reduce,
                           Overlap overlap, std::size_t maxQueuedBytes, unsigned workers)
    : destination_(std::move(destination)), packedDestination_(std::move(packedDestination)), reduce_(reduce),
      overlap_(overlap), maxQueuedBytes_(maxQueuedBytes) {
    YV_CHECK(destination_);
    start(workers);
}

void RegionWriter::start(unsigned workers) {
    const unsigned n = workers == 0 ? 2 : workers;
    threads_.reserve(n);
    try {
        for (unsigned i = 0; i < n; ++i) threads_.emplace_back([this] { work(); });
    } catch (...) {
        stop();
        throw;
    }
}

RegionWriter::~RegionWriter() { stop(); }

void RegionWriter::stop() {
    {
        std::lock_guard lock(mutex_);
        for (const Job& job : queue_) heldBytes_ -= job.bytes;
        queue_.clear();
        closing_ = true;
    }
    workReady_.notify_all();
    spaceFree_.notify_all();
    for (std::thread& t : threads_)
        if (t.joinable()) t.join();
}

void RegionWriter::submit(std::uint64_t id, glm::ivec3 min, glm::ivec3 max,
                          std::vector<BrickAccumulator> accumulators) {
    // Checked here, in the caller's thread: resolveBrick reads the words unchecked.
    const std::size_t words = std::size_t(wordsPerVoxel(reduce_)) * kBrickVoxels;
    const std::size_t albedoWords = std::size_t(wordsPerVoxel(reduce_, true)) * kBrickVoxels;
    for (const BrickAccumulator& a : accumulators)
        if (a.words.size() != words && a.words.size() != albedoWords)
            throw Error("region " + std::to_string(id) + ": accumulator of brick key " + std::to_string(a.key) +
                        " has " + std::to_string(a.words.size()) + " words, " + toString(reduce_) + " needs " +
                        std::to_string(words));
    Job job{id, min, max, std::move(accumulators), {}, false, 0};
    job.bytes = heldBytes(job.accumulators);
    enqueue(std::move(job));
}

void RegionWriter::submitResolved(std::uint64_t id, glm::ivec3 min, glm::ivec3 max, PackedBricks bricks) {
    Job job{id, min, max, {}, std::move(bricks), true, 0};
    job.bytes = job.resolved.bytes();
    enqueue(std::move(job));
}

void RegionWriter::enqueue(Job job) {
    const std::uint64_t id = job.id;
    std::unique_lock lock(mutex_);
    if (closing_) throw Error("region " + std::to_string(id) + ": submitted after the region writer finished");
    const auto waitStart = Clock::now();
    spaceFree_.wait(lock, [&] {
        return error_ || closing_ || heldBytes_ == 0 || heldBytes_ + job.bytes <= maxQueuedBytes_;
    });
    stats_.submitWaitSeconds += secondsSince(waitStart);
    traceSpanSince("wait for room in the writer's queue", waitStart);
    if (error_) std::rethrow_exception(error_);
    if (closing_) throw Error("region " + std::to_string(id) + ": submitted after the region writer finished");
    heldBytes_ += job.bytes;
    stats_.peakQueuedBytes = std::max<std::uint64_t>(stats_.peakQueuedBytes, heldBytes_);
    queue_.push_back(std::move(job));
    lock.unlock();
    workReady_.notify_one();
}

void RegionWriter::work() {
    for (;;) {
        Job job;
        bool skip;
        {
            std::unique_lock lock(mutex_);
            workReady_.wait(lock, [&] { return !queue_.empty() || closing_; });
            if (queue_.empty()) return;
            job = std::move(queue_.front());
            queue_.pop_front();
            skip = error_ != nullptr; // after a failure the run is lost: drop, don't write
        }
        std::exception_ptr error;
        if (!skip) {
            try {
                process(job);
            } catch (...) {
                error = std::current_exception();
            }
        }
        job.accumulators = {};
        job.resolved = {};
        {
            std::lock_guard lock(mutex_);
            if (error && !error_) error_ = error;
            heldBytes_ -= job.bytes;
        }
        spaceFree_.notify_all();
    }
}

PackedBricks RegionWriter::recycledPackedBricks() {
    std::lock_guard lock(mutex_);
    if (spareStorage_.empty()) return {};
    PackedBricks bricks = std::move(spareStorage_.back());
    spareStorage_.pop_back();
    return bricks;
}

void RegionWriter::recycle(PackedBricks&& bricks) {
    // Spares hold no region, so the queue's bound does not count them: each
    // is kept only within its share of that bound (of 64 MiB at least), so
    // all of them together hold at most as much again.
    if (bricks.bytes() > std::max(maxQueuedBytes_, std::size_t(64) << 20) / kSpareStorage) return;
    bricks.clear();
    std::lock_guard lock(mutex_);
    if (spareStorage_.size() < kSpareStorage) spareStorage_.push_back(std::move(bricks));
}

std::vector<VoxelBrick> RegionWriter::bricksOf(Job& job, ResolveTally& tally) {
    if (job.isResolved) {
        std::vector<VoxelBrick> bricks = unpackBricks(job.resolved, &tally);
        recycle(std::move(job.resolved));
        job.resolved = {};
        return bricks;
    }
    std::vector<VoxelBrick> bricks(job.accumulators.size());
    std::vector<std::uint8_t> keep(job.accumulators.size());
    std::vector<ResolveTally> tallies(job.accumulators.size());
    tbb::parallel_for(std::size_t(0), bricks.size(), [&](std::size_t i) {
        keep[i] = resolveBrick(reduce_, overlap_, job.accumulators[i], bricks[i], &tallies[i]);
    });
    for (const ResolveTally& t : tallies) tally += t;
    job.accumulators = {};
    std::size_t kept = 0;
    for (std::size_t i = 0; i < bricks.size(); ++i)
        if (keep[i]) {
            if (kept != i) bricks[kept] = bricks[i];
            ++kept;
        }
    bricks.resize(kept);
    return bricks;
}

void RegionWriter::process(Job& job) {
    const TraceSpan span("write a region");
    const auto t = Clock::now();
    ResolveTally tally;
    double resolveSeconds = 0.0;
    RegionWriteTimings timings;
    RegionInfo info;
    // Without a store the destination's region: its id, bounds and counts.
    const auto handedOver = [&](std::uint64_t brickCount) {
        info.id = job.id;
        info.min = job.min;
        info.max = job.max;
        info.brickCount = brickCount;
        info.activeVoxels = tally.activeVoxels;
    };
    if (job.isResolved && packedDestination_) {
        // Straight on, packed; the tally from the headers, in header order as unpackBricks sums it.
        for (const PackedBrickHeader& h : job.resolved.headers) tally += tallyOf(h);
        resolveSeconds = secondsSince(t);
        handedOver(job.resolved.headers.size());
        packedDestination_(job.id, job.resolved);
        recycle(std::move(job.resolved));
        job.resolved = {};
    } else {
        std::vector<VoxelBrick> bricks = bricksOf(job, tally);
        resolveSeconds = secondsSince(t);
        if (store_) {
            info = store_->writeRegion(job.id, job.min, job.max, std::move(bricks), &timings);
        } else {
            handedOver(bricks.size());
            destination_(job.id, std::move(bricks));
        }
    }

    std::lock_guard lock(mutex_);
    results_.push_back(info);
    stats_.resolveSeconds += resolveSeconds;
    stats_.encodeSeconds += timings.encodeSeconds;
    stats_.writeSeconds += timings.writeSeconds;
    stats_.regionsWritten += 1;
    stats_.bricksWritten += info.brickCount;
    stats_.bytesWritten += info.bytesOnDisk;
    regionTallies_.emplace_back(job.id, tally);
}

std::vector<RegionInfo> RegionWriter::finish() {
    {
        std::lock_guard lock(mutex_);
        closing_ = true;
    }
    workReady_.notify_all();
    spaceFree_.notify_all();
    for (std::thread& t : threads_)
        if (t.joinable()) t.join();
    if (error_) std::rethrow_exception(error_);
    std::sort(results_.begin(), results_.end(), [](const RegionInfo& a, const RegionInfo& b) { return a.id < b.id; });
    return results_;
}

RegionWriterStats RegionWriter::stats() const {
    std::lock_guard lock(mutex_);
    RegionWriterStats stats = stats_;
    // Summed in region order, not in the order workers finished: the same
    // doubles in every run.
    std::vector<std::pair<std::uint64_t, ResolveTally>> tallies = regionTallies_;
    std::sort(tallies.begin(), tallies.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [id, tally] : tallies) stats.tally += tally;
    return stats;
}

} // namespace yv

#include "core/parallel_copy.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <stop_token>
#include <thread>
#include <vector>

namespace yv {
namespace {

/// Copies below this many bytes a piece stay on the calling thread: waking
/// a thread costs more than the copy.
constexpr std::size_t kLeastPiece = std::size_t(2) << 20;

/// Threads that wait for a copy, started at the first large one and stopped
/// at exit. One copy at a time.
class CopyThreads {
  public:
    static CopyThreads& instance() {
        static CopyThreads threads;
        return threads;
    }

    std::size_t helpers() const { return threads_.size(); }

    /// Copies on the threads and the caller; false (nothing copied) while
    /// another copy holds them.
    bool copy(char* to, const char* from, std::size_t bytes, std::size_t pieces) {
        std::unique_lock caller(callers_, std::try_to_lock);
        if (!caller) return false;
        Job job{to, from, bytes, pieces};
        {
            std::lock_guard lock(mutex_);
            job_ = &job;
            ++generation_;
        }
        wake_.notify_all();
        work(job);
        std::unique_lock lock(mutex_);
        // Every piece copied, and no helper still holding the job.
        done_.wait(lock, [&] { return job.finished == job.pieces && job.inside == 0; });
        job_ = nullptr;
        return true;
    }

  private:
    struct Job {
        char* to;
        const char* from;
        std::size_t bytes, pieces;
        std::atomic<std::size_t> next{0}, finished{0};
        int inside = 0; ///< helpers working on it (under mutex_)
    };

    CopyThreads() {
        const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
        // At least one helper, so that two cores copy side by side too.
        const unsigned count = std::clamp(cores / 2, 2u, kCopyThreads);
        for (unsigned i = 1; i < count; ++i) threads_.emplace_back([this](std::stop_token stop) { serve(stop); });
    }
    ~CopyThreads() {
        for (std::jthread& t : threads_) t.request_stop();
        wake_.notify_all();
    }

    void work(Job& job) {
        const std::size_t piece = (job.bytes + job.pieces - 1) / job.pieces;
        for (std::size_t p; (p = job.next++) < job.pieces;) {
            const std::size_t at = p * piece;
            std::memcpy(job.to + at, job.from + at, std::min(piece, job.bytes - at));
            if (++job.finished == job.pieces) {
                std::lock_guard lock(mutex_); // so the caller cannot miss the wake-up
                done_.notify_all();
            }
        }
    }

    void serve(std::stop_token stop) {
        std::uint64_t seen = 0;
        std::unique_lock lock(mutex_);
        for (;;) {
            wake_.wait(lock, stop, [&] { return job_ && generation_ != seen; });
            if (stop.stop_requested()) return;
            seen = generation_;
            Job& job = *job_;
            ++job.inside;
            lock.unlock();
            work(job);
            lock.lock();
            --job.inside;
            done_.notify_all();
        }
    }

    std::mutex callers_;
    std::mutex mutex_;
    std::condition_variable_any wake_;
    std::condition_variable_any done_;
    Job* job_ = nullptr;
    std::uint64_t generation_ = 0;
    std::vector<std::jthread> threads_;
};

} // namespace

unsigned copyHelperThreads() { return unsigned(CopyThreads::instance().helpers()); }

void copyInParallel(void* to, const void* from, std::size_t bytes) {
    if (bytes >= 2 * kLeastPiece) {
        CopyThreads& threads = CopyThreads::instance();
        const std::size_t pieces = std::min<std::size_t>(bytes / kLeastPiece, 4 * (threads.helpers() + 1));
        if (threads.helpers() > 0 &&
            threads.copy(static_cast<char*>(to), static_cast<const char*>(from), bytes, pieces))
            return;
    }
    if (bytes) std::memcpy(to, from, bytes);
}

} // namespace yv

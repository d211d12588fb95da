#include "vdb/chunked_output.h"

#include "core/atomic_file.h"
#include "core/error.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <mutex>
#include <new>
#include <thread>
#include <vector>

namespace yv {
namespace {

struct FreeDeleter {
    void operator()(std::uint8_t* p) const { std::free(p); }
};
using AlignedBuffer = std::unique_ptr<std::uint8_t, FreeDeleter>;

std::uint64_t checkedChunkBytes(std::uint64_t chunkBytes) {
    const std::uint64_t bytes = chunkBytes ? chunkBytes : ChunkedOutput::kDefaultChunkBytes;
    YV_CHECK(bytes % ChunkedOutput::kAlignment == 0);
    return bytes;
}

} // namespace

ChunkedOutput::ChunkedOutput(int fd, std::string what, std::uint64_t chunkBytes, WriteCall write)
    : what_(std::move(what)), chunkBytes_(checkedChunkBytes(chunkBytes)), write_(write ? write : ::pwrite), fd_(fd) {
    // Opened through the cache, then switched: a file system without
    // O_DIRECT (some network and overlay ones) refuses the switch with
    // EINVAL, where an open with O_DIRECT would have left an empty file.
    const int flags = ::fcntl(fd_, F_GETFL);
    direct_ = flags >= 0 && ::fcntl(fd_, F_SETFL, flags | O_DIRECT) == 0;
}

void ChunkedOutput::dropDirect() {
    static std::mutex mutex;
    const std::lock_guard lock(mutex);
    if (!direct_) return;
    const int flags = ::fcntl(fd_, F_GETFL);
    if (flags < 0 || ::fcntl(fd_, F_SETFL, flags & ~O_DIRECT) != 0)
        throw Error(what_ + ": cannot turn direct writes off: " + errnoText(errno));
    direct_ = false;
}

void ChunkedOutput::writeChunk(const std::uint8_t* bytes, std::uint64_t count, std::uint64_t at) {
    std::uint64_t done = 0;
    while (done < count) {
        // Whether this call went direct: another thread may turn direct
        // writes off between the call and the look at its error.
        const bool wasDirect = direct_;
        const ssize_t n = write_(fd_, bytes + done, count - done, off_t(at + done));
        if (n < 0 && errno == EINTR) continue;
        if (n < 0 && errno == EINVAL && wasDirect) {
            dropDirect(); // a block size beyond the alignment: the rest through the cache
            continue;
        }
        if (n < 0) throw Error(what_ + ": " + errnoText(errno));
        if (n == 0) throw Error(what_ + ": the write made no progress");
        done += std::uint64_t(n);
        // A direct write cut short mid-block (a full disk, a signal): the
        // rest is no longer aligned, and goes through the cache, whose next
        // write says why it stops.
        if (done < count && done % kAlignment != 0 && wasDirect) dropDirect();
    }
}

void ChunkedOutput::fillAndWrite(std::uint8_t* buffer, std::uint64_t at, std::uint64_t bytes, const Fill& fill) {
    fill(at, std::span(buffer, bytes));
    // The last chunk is padded to the alignment; the file is cut back to its size after.
    const std::uint64_t padded = (bytes + kAlignment - 1) / kAlignment * kAlignment;
    std::memset(buffer + bytes, 0, padded - bytes);
    writeChunk(buffer, padded, at);
}

void ChunkedOutput::patch(std::uint64_t at, std::span<const std::uint8_t> bytes) {
    dropDirect(); // an unaligned write
    writeChunk(bytes.data(), bytes.size(), at);
}

void ChunkedOutput::write(std::uint64_t size, const Fill& fill) {
    writeRange(0, size, fill);
    if (size % kAlignment != 0 && ::ftruncate(fd_, off_t(size)) != 0)
        throw Error(what_ + ": cannot set the file's size: " + errnoText(errno));
}

void ChunkedOutput::writeRange(std::uint64_t begin, std::uint64_t end, const Fill& fill) {
    YV_CHECK(begin % kAlignment == 0 && begin <= end);
    const std::uint64_t chunks = (end - begin + chunkBytes_ - 1) / chunkBytes_;
    tbb::enumerable_thread_specific<AlignedBuffer> buffers(
        [&] { return AlignedBuffer(static_cast<std::uint8_t*>(std::aligned_alloc(kAlignment, chunkBytes_))); });
    // TBB's own count, not the machine's: with fewer cores to run on (taskset,
    // an MPI rank bound to one core, a tbb::global_control limit) an arena
    // of the machine's size asked TBB for workers it may not have, and TBB
    // printed "The number of workers is currently limited to 0" to stderr.
    const int allowed = int(std::min<std::size_t>(
        std::size_t(tbb::this_task_arena::max_concurrency()),
        tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)));
    const int writers = std::clamp(allowed, 1, kMaxWriters);
    tbb::task_arena arena(writers);
    arena.execute([&] {
        tbb::parallel_for(std::uint64_t(0), chunks, [&](std::uint64_t c) {
            AlignedBuffer& buffer = buffers.local();
            if (!buffer) throw std::bad_alloc();
            const std::uint64_t at = begin + c * chunkBytes_;
            fillAndWrite(buffer.get(), at, std::min(chunkBytes_, end - at), fill);
        });
    });
}

void ChunkedOutput::writeRangeOnThreads(std::uint64_t begin, std::uint64_t end, const Fill& fill, int threads) {
    YV_CHECK(begin % kAlignment == 0 && begin <= end && threads >= 1);
    const std::uint64_t chunks = (end - begin + chunkBytes_ - 1) / chunkBytes_;
    std::atomic<std::uint64_t> next{0};
    std::atomic<bool> failed{false};
    std::exception_ptr error;
    std::mutex errorMutex;
    const auto work = [&] {
        try {
            AlignedBuffer buffer(static_cast<std::uint8_t*>(std::aligned_alloc(kAlignment, chunkBytes_)));
            if (!buffer) throw std::bad_alloc();
            for (std::uint64_t c = next++; c < chunks && !failed; c = next++) {
                const std::uint64_t at = begin + c * chunkBytes_;
                fillAndWrite(buffer.get(), at, std::min(chunkBytes_, end - at), fill);
            }
        } catch (...) {
            const std::lock_guard lock(errorMutex);
            if (!error) error = std::current_exception();
            failed = true;
        }
    };
    {
        std::vector<std::jthread> pool;
        for (std::uint64_t t = 1; t < std::min(std::uint64_t(threads), chunks); ++t) pool.emplace_back(work);
        work();
    }
    if (error) std::rethrow_exception(error);
}

} // namespace yv

#include "vdb/chunked_output.h"

#include "core/error.h"
#include "vdb/spill_file.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>

namespace yv {
namespace {

struct FreeDeleter {
    void operator()(std::uint8_t* p) const { std::free(p); }
};
using AlignedBuffer = std::unique_ptr<std::uint8_t, FreeDeleter>;

int openNew(const std::string& path, bool direct) {
    return ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | (direct ? O_DIRECT : 0), 0644);
}

/// File systems without O_DIRECT (tmpfs, some network and overlay ones)
/// refuse the open with EINVAL: the file is then written through the cache.
int openOutput(const std::string& path, const std::string& what, std::atomic<bool>& direct) {
    int fd = openNew(path, true);
    direct = fd >= 0;
    if (fd < 0 && errno == EINVAL) fd = openNew(path, false);
    if (fd < 0) throw Error(what + ": cannot create it: " + errnoText(errno));
    return fd;
}

} // namespace

ChunkedOutput::ChunkedOutput(const std::string& path, std::string what, std::uint64_t chunkBytes)
    : what_(std::move(what)), fd_(openOutput(path, what_, direct_)),
      chunkBytes_(chunkBytes ? chunkBytes : kDefaultChunkBytes) {
    YV_CHECK(chunkBytes_ > 0 && chunkBytes_ % kAlignment == 0);
}

void ChunkedOutput::dropDirect() {
    const int flags = ::fcntl(fd_.get(), F_GETFL);
    if (flags < 0 || ::fcntl(fd_.get(), F_SETFL, flags & ~O_DIRECT) != 0)
        throw Error(what_ + ": cannot turn direct writes off: " + errnoText(errno));
}

void ChunkedOutput::write(std::uint64_t size, const Fill& fill) {
    const std::uint64_t chunks = (size + chunkBytes_ - 1) / chunkBytes_;
    tbb::enumerable_thread_specific<AlignedBuffer> buffers(
        [&] { return AlignedBuffer(static_cast<std::uint8_t*>(std::aligned_alloc(kAlignment, chunkBytes_))); });
    std::mutex modeMutex;
    tbb::parallel_for(std::uint64_t(0), chunks, [&](std::uint64_t c) {
        AlignedBuffer& buffer = buffers.local();
        if (!buffer) throw std::bad_alloc();
        const std::uint64_t at = c * chunkBytes_, bytes = std::min(chunkBytes_, size - at);
        fill(at, std::span(buffer.get(), bytes));
        // The last chunk of a direct write is padded to the alignment; the
        // file is cut back to its size after.
        const std::uint64_t padded = (bytes + kAlignment - 1) / kAlignment * kAlignment;
        std::memset(buffer.get() + bytes, 0, padded - bytes);
        const auto buffered = [&] {
            const std::lock_guard lock(modeMutex);
            if (direct_) {
                dropDirect();
                direct_ = false;
            }
        };
        for (;;) {
            const ssize_t n = ::pwrite(fd_.get(), buffer.get(), padded, off_t(at));
            if (n == ssize_t(padded)) break;
            if (n < 0 && errno == EINTR) continue;
            if (n < 0 && errno == EINVAL && direct_) {
                // A block size beyond the alignment: the rest goes through the cache.
                buffered();
                continue;
            }
            if (n < 0) throw Error(what_ + ": " + errnoText(errno));
            // A short write (a full disk, or a signal): the rest, unaligned,
            // through the cache and writeAllAt, which says why it stops.
            buffered();
            writeAllAt(fd_.get(), std::span<const std::uint8_t>(buffer.get() + n, padded - std::size_t(n)),
                       at + std::uint64_t(n), what_);
            break;
        }
    });
    if (chunks > 0 && size % kAlignment != 0 && ::ftruncate(fd_.get(), off_t(size)) != 0)
        throw Error(what_ + ": cannot set the file's size: " + errnoText(errno));
}

} // namespace yv

// A new file written in large chunks side by side, past the page cache where
// the file system allows (O_DIRECT). On the GPU machine's disk a buffered
// write with fsync ran at 1.0 GB/s and a direct one at 1.4 GB/s (dd, 4 GiB),
// and a multi-gigabyte .vdb written through the cache also evicts the pages
// the rest of the run still wants. Direct writes need aligned offsets,
// lengths and memory: the file is cut into chunks of a fixed size at fixed
// offsets, each filled by the caller into an aligned buffer, the last one
// padded and the file truncated back to its size.
#pragma once

#include <sys/types.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>

namespace yv {

class ChunkedOutput {
  public:
    /// Default chunk: large enough to keep the disk's queue full with a few
    /// threads, small enough that a buffer per thread costs little.
    static constexpr std::uint64_t kDefaultChunkBytes = 16ull << 20;
    /// Alignment of direct writes (offsets, lengths, memory): 4096 covers
    /// disks of 512- and 4096-byte blocks.
    static constexpr std::uint64_t kAlignment = 4096;
    /// Chunks filled and written at once, at most: a few keep the disk busy,
    /// and each holds a buffer.
    static constexpr int kMaxWriters = 16;

    /// pwrite's signature: tests put a function in its place that fails the
    /// way file systems do.
    using WriteCall = ssize_t (*)(int fd, const void* bytes, std::size_t count, off_t offset);

    /// Writes to the open, empty file `fd` (a PendingFile's: it stays the
    /// caller's to sync, close and publish). `what` starts every error
    /// message. `chunkBytes` (a multiple of kAlignment; 0: the default) is
    /// smaller in tests, so that chunks cut through what the caller writes.
    ChunkedOutput(int fd, std::string what, std::uint64_t chunkBytes = 0, WriteCall write = nullptr);
    ChunkedOutput(const ChunkedOutput&) = delete;
    ChunkedOutput& operator=(const ChunkedOutput&) = delete;

    /// Fills bytes [at, at + out.size()) of the file. Called from several
    /// threads at once, for disjoint ranges; throws to fail the write.
    using Fill = std::function<void(std::uint64_t at, std::span<std::uint8_t> out)>;

    /// Writes the whole file of `size` bytes, chunk by chunk on up to
    /// kMaxWriters threads. Where the file system refuses direct writes (at
    /// the start, or a write with EINVAL or cut short), the chunks go through
    /// the page cache. Throws yv::Error "WHAT: reason" on failure.
    void write(std::uint64_t size, const Fill& fill);

    /// Writes bytes [begin, end) of the file the same way, chunks counted
    /// from `begin` (a multiple of kAlignment), for a file written in parts
    /// (vdb/leaf_stream.h). `end` is a multiple of kAlignment too, or the
    /// file's end: the last chunk is then padded, and the caller cuts the
    /// file back to its size.
    void writeRange(std::uint64_t begin, std::uint64_t end, const Fill& fill);
    /// writeRange on `threads` threads of its own instead of TBB's: for a
    /// writer beside TBB work that keeps every worker busy (the regions'
    /// encoding, vdb/leaf_stream.h), where TBB's chunks waited for a worker
    /// and the disk for the chunks.
    void writeRangeOnThreads(std::uint64_t begin, std::uint64_t end, const Fill& fill, int threads);

    /// Writes `bytes` at `at` again, through the page cache (after write(): the
    /// header of a file whose checksums are known only once it is written).
    void patch(std::uint64_t at, std::span<const std::uint8_t> bytes);

    /// Whether the chunks go past the page cache.
    bool direct() const { return direct_.load(); }

  private:
    void writeChunk(const std::uint8_t* bytes, std::uint64_t count, std::uint64_t at);
    /// Fills `bytes` at `at` into `buffer` (a chunk's) and writes them, padded to the alignment.
    void fillAndWrite(std::uint8_t* buffer, std::uint64_t at, std::uint64_t bytes, const Fill& fill);
    void dropDirect();

    std::string what_;
    std::uint64_t chunkBytes_;
    WriteCall write_;
    int fd_;
    std::atomic<bool> direct_{false};
};

} // namespace yv

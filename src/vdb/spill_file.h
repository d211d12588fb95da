// Scratch space for bytes that are made in one order and written out in
// another: leaves are encoded as regions finish, but a .vdb wants them in
// tree order. Its first part is memory and the rest an unnamed file (on
// O_TMPFILE, or a name removed at once), so nothing is left behind however
// the process ends.
//
// Why memory first: the file's pages stayed in the page cache between the
// append and the read anyway, and letting them go held the end of the run
// about 0.08 s a GB on one core (0.24 s for 3 GB on the dev machine), while
// the same bytes in 2 MiB pages are freed in milliseconds; appends and
// reads become copies instead of system calls (on an H100 the sweater at
// 8192 ran 10.1 and 10.6 s against 10.8 and 11.1 s, its writers' CPU time
// halved). The file takes over past the memory part, so a run larger than
// the machine's memory still fits.
#pragma once

#include "core/atomic_file.h"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace yv {

class SpillFile {
  public:
    /// Opens scratch space whose first `memoryBytes` are memory (taken as
    /// they are written) and the rest an unnamed file in `dir` (the output's
    /// directory: same file system, and not /tmp, which may be memory).
    /// `purpose` names it in errors.
    SpillFile(const std::string& dir, std::string purpose, std::uint64_t memoryBytes = 0);
    ~SpillFile();
    SpillFile(const SpillFile&) = delete;
    SpillFile& operator=(const SpillFile&) = delete;

    /// Appends `bytes` and returns where they start. Thread-safe: each call
    /// reserves its own range, then writes without a lock.
    std::uint64_t append(std::span<const std::uint8_t> bytes);
    /// Reserves `bytes` at the end and returns where they start; writeAt
    /// then fills them, in pieces from several threads if need be.
    std::uint64_t reserve(std::uint64_t bytes) { return end_.fetch_add(bytes); }
    /// Writes `bytes` at `offset` (within a range from reserve). Thread-safe.
    void writeAt(std::uint64_t offset, std::span<const std::uint8_t> bytes);
    /// Reads `out.size()` bytes at `offset`. Thread-safe.
    void read(std::uint64_t offset, std::span<std::uint8_t> out) const;
    std::uint64_t size() const { return end_.load(); }
    /// Of size(), the bytes held in memory.
    std::uint64_t bytesInMemory() const { return std::min(end_.load(), memoryBytes_); }

  private:
    /// Of `bytes` at `offset`, how many from the start lie in the memory part.
    std::size_t inMemory(std::uint64_t offset, std::size_t bytes) const;

    std::string where_;
    Fd fd_;
    std::uint8_t* memory_ = nullptr; ///< memoryBytes_ of address space, pages taken as written
    std::uint64_t memoryBytes_ = 0;
    std::atomic<std::uint64_t> end_{0};
};

/// The memory part a .vdb writer's scratch space gets: a quarter of the
/// machine's memory, at most half of what is available now, unless
/// YV_SPILL_MEMORY_MB says otherwise (0: all in the file). Throws yv::Error
/// on a value that is not a count of MB.
std::uint64_t spillMemoryBytes();

/// pwrite of all of `bytes` at `offset`, retried on short writes and EINTR;
/// throws yv::Error "WHAT: reason" on failure.
void writeAllAt(int fd, std::span<const std::uint8_t> bytes, std::uint64_t offset, const std::string& what);

} // namespace yv

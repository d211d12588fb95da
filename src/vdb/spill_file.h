// A scratch file for bytes that are made in one order and written out in
// another: leaves are encoded as regions finish, but a .vdb wants them in
// tree order. The file has no name (O_TMPFILE, or a name removed at once),
// so nothing is left behind however the process ends; its pages mostly stay
// in the page cache between the append and the read.
#pragma once

#include "core/atomic_file.h"

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace yv {

class SpillFile {
  public:
    /// Opens an unnamed file in `dir` (the output's directory: same file
    /// system, and not /tmp, which may be memory). `purpose` names it in errors.
    SpillFile(const std::string& dir, std::string purpose);
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

  private:
    std::string where_;
    Fd fd_;
    std::atomic<std::uint64_t> end_{0};
};

/// pwrite of all of `bytes` at `offset`, retried on short writes and EINTR;
/// throws yv::Error "WHAT: reason" on failure.
void writeAllAt(int fd, std::span<const std::uint8_t> bytes, std::uint64_t offset, const std::string& what);

} // namespace yv

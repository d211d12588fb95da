// POSIX file helpers shared by every writer of yarnvox files: whole-file
// reads, and writes that are atomic (temporary name, fsync, rename, fsync of
// the directory), so a crash never leaves a file that looks complete.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace yv {

/// strerror-like text of an errno value.
std::string errnoText(int err);

/// Owns a file descriptor so every early exit closes it; release() hands it
/// back when the caller must see close()'s result.
class Fd {
  public:
    explicit Fd(int fd) : fd_(fd) {}
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
    ~Fd();
    int get() const { return fd_; }
    int release() { return std::exchange(fd_, -1); }

  private:
    int fd_;
};

/// The whole file; nullopt when it does not exist. Throws yv::Error naming the path otherwise.
std::optional<std::vector<std::uint8_t>> readWholeFile(const std::string& path);

/// fsync of an open directory (ignored where the file system cannot sync directories).
void fsyncDir(int dirFd, const std::string& dir);

/// Writes `parts` to dir/name via a temporary name in the same directory,
/// fsync, rename and a directory fsync: after a crash the file is either the
/// old one, absent, or complete. On failure the temporary is removed and
/// yv::Error says "cannot write PATH: STEP TMP: reason".
void writeAtomically(const std::string& dir, int dirFd, const std::string& name,
                     std::span<const std::span<const std::uint8_t>> parts);

/// writeAtomically for one buffer, opening the file's directory itself.
void writeFileAtomically(const std::string& path, std::span<const std::uint8_t> bytes);

} // namespace yv

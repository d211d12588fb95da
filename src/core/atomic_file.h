// POSIX file helpers shared by every writer of yarnvox files: whole-file
// reads, and the one way a file is published (PendingFile): written under a
// temporary name beside its target, fsynced, renamed over the target, and the
// directory fsynced, so a crash never leaves a file that looks complete.
#pragma once

#include <cstddef>
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

/// A file on its way to `path`: written under PATH.partial-PID-N in the same
/// directory (created exclusively, so two writers of one output never share
/// it), then published: fsync, rename over `path`, fsync of the directory.
/// Until publish() returns, `path` is untouched: after a crash it is the old
/// file, absent, or complete. A `path` that is not a regular file (a link, a
/// device, a FIFO, a directory: nonRegularKind) is never replaced: refused
/// when the PendingFile is made and again before the rename. Every failure
/// throws yv::Error "cannot write PATH: ..."; the temporary is removed unless
/// published.
class PendingFile {
  public:
    /// `dirFd`: an open descriptor of the directory of `path` that the caller
    /// holds (the brick store's), or -1 to open one here.
    explicit PendingFile(std::string path, int dirFd = -1);
    ~PendingFile();
    PendingFile(const PendingFile&) = delete;
    PendingFile& operator=(const PendingFile&) = delete;

    /// The temporary's descriptor, for writers of their own (ChunkedOutput);
    /// -1 after sync().
    int fd() const { return fd_; }
    const std::string& path() const { return path_; }
    const std::string& temporaryPath() const { return tmp_; }
    /// One past the last byte written through append or writeAt.
    std::uint64_t size() const { return size_; }

    /// Appends `n` bytes at size().
    void append(const void* data, std::size_t n) { writeAt(size_, data, n); }
    void append(std::span<const std::uint8_t> bytes) { append(bytes.data(), bytes.size()); }
    /// Writes `n` bytes at byte `offset` (for writers that seek back to a header).
    void writeAt(std::uint64_t offset, const void* data, std::size_t n);
    /// fsync and close: the data are on disk, still under the temporary name.
    void sync();
    /// Renames the temporary over `path` (after sync(), which runs here when
    /// it has not) and fsyncs the directory.
    void publish();

  private:
    [[noreturn]] void fail(const char* step, int err) const;

    std::string path_, tmp_, dir_;
    int fd_ = -1, dirFd_ = -1;
    bool ownsDirFd_ = false, published_ = false;
    std::uint64_t size_ = 0;
};

/// Publishes `parts`, back to back, as the file `path` (PendingFile).
void writeFileAtomically(const std::string& path, std::span<const std::span<const std::uint8_t>> parts, int dirFd = -1);

/// writeFileAtomically for one buffer.
void writeFileAtomically(const std::string& path, std::span<const std::uint8_t> bytes);

} // namespace yv

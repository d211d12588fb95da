// A file read by position from any thread: the .vdb reader and the brick
// store's chunk reader read only the byte ranges they need, never the
// whole file, and every read is checked against the file's end.
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace yv {

/// An open file, read by position from any thread (pread).
class ReadOnlyFile {
  public:
    /// Throws yv::Error naming `path` when it cannot be opened.
    explicit ReadOnlyFile(std::string path);
    ~ReadOnlyFile();
    ReadOnlyFile(const ReadOnlyFile&) = delete;
    ReadOnlyFile& operator=(const ReadOnlyFile&) = delete;

    const std::string& path() const { return path_; }
    std::uint64_t size() const { return size_; }
    /// Fills `out` from byte `at`; throws yv::Error naming the file, the
    /// byte and `what` when the file ends first or the read fails.
    void read(std::uint64_t at, std::span<std::uint8_t> out, const std::string& what) const;

  private:
    std::string path_;
    int fd_ = -1;
    std::uint64_t size_ = 0;
};

} // namespace yv

// Reading a file front to back through a small window, with every read
// checked against the file's end: the .vdb reader walks headers and
// topology with it, so a file of any size is parsed in a few megabytes,
// and a truncated one is refused where it ends instead of read past.
#pragma once

#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

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

/// Sequential reads from a ReadOnlyFile through a window.
class FileCursor {
  public:
    FileCursor(const ReadOnlyFile& file, std::uint64_t at, std::size_t windowBytes = 4u << 20);

    std::uint64_t position() const { return at_; }
    void seek(std::uint64_t at);
    void skip(std::uint64_t bytes) { seek(at_ + bytes); }
    /// The next `bytes` bytes (valid until the next call); `what` names them in errors.
    std::span<const std::uint8_t> bytes(std::size_t bytes, const std::string& what);
    template <typename T> T pod(const std::string& what) {
        static_assert(std::is_trivially_copyable_v<T>);
        T value;
        std::memcpy(&value, bytes(sizeof value, what).data(), sizeof value);
        return value;
    }
    /// An OpenVDB string: a u32 length then the bytes, at most `maxBytes`.
    std::string string(const std::string& what, std::uint32_t maxBytes = 1u << 20);
    /// "PATH: byte N: " for messages about what is read next.
    std::string where() const;

  private:
    const ReadOnlyFile& file_;
    std::uint64_t at_ = 0;
    std::size_t windowBytes_;
    std::uint64_t windowAt_ = 0;
    std::vector<std::uint8_t> window_;
};

} // namespace yv

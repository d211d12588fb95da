// Reading a file front to back through a small window, with every read
// checked against the file's end: the .vdb reader walks headers and
// topology with it, so a file of any size is parsed in a few megabytes,
// and a truncated one is refused where it ends instead of read past.
#pragma once

#include "core/read_only_file.h"

#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

namespace yv {

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

#include "vdb/file_cursor.h"

#include "core/error.h"

#include <algorithm>

namespace yv {

FileCursor::FileCursor(const ReadOnlyFile& file, std::uint64_t at, std::size_t windowBytes)
    : file_(file), at_(at), windowBytes_(windowBytes) {}

void FileCursor::seek(std::uint64_t at) { at_ = at; }

std::span<const std::uint8_t> FileCursor::bytes(std::size_t n, const std::string& what) {
    const bool inWindow = at_ >= windowAt_ && at_ - windowAt_ + n <= window_.size();
    if (!inWindow) {
        if (at_ > file_.size() || n > file_.size() - at_)
            throw Error(where() + what + " needs " + std::to_string(n) + " bytes, but the file ends at byte " +
                        std::to_string(file_.size()) + " (truncated?)");
        window_.resize(std::size_t(std::min<std::uint64_t>(std::max(n, windowBytes_), file_.size() - at_)));
        file_.read(at_, window_, what);
        windowAt_ = at_;
    }
    const std::span<const std::uint8_t> out(window_.data() + (at_ - windowAt_), n);
    at_ += n;
    return out;
}

std::string FileCursor::string(const std::string& what, std::uint32_t maxBytes) {
    const std::uint64_t start = at_;
    const auto length = pod<std::uint32_t>(what + "'s length");
    if (length > maxBytes) {
        at_ = start;
        throw Error(where() + what + " declares " + std::to_string(length) + " bytes, more than the " +
                    std::to_string(maxBytes) + " it may have");
    }
    const auto b = bytes(length, what);
    return std::string(reinterpret_cast<const char*>(b.data()), b.size());
}

std::string FileCursor::where() const { return file_.path() + ": byte " + std::to_string(at_) + ": "; }

} // namespace yv

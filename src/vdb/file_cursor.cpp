#include "vdb/file_cursor.h"

#include "core/error.h"

#include <algorithm>
#include <cerrno>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace yv {

ReadOnlyFile::ReadOnlyFile(std::string path) : path_(std::move(path)) {
    fd_ = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) throw Error(path_ + ": cannot open: " + std::strerror(errno));
    struct stat st {};
    if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
        ::close(fd_);
        throw Error(path_ + ": not a regular file");
    }
    size_ = std::uint64_t(st.st_size);
}

ReadOnlyFile::~ReadOnlyFile() { ::close(fd_); }

void ReadOnlyFile::read(std::uint64_t at, std::span<std::uint8_t> out, const std::string& what) const {
    if (at > size_ || out.size() > size_ - at)
        throw Error(path_ + ": byte " + std::to_string(at) + ": " + what + " needs " + std::to_string(out.size()) +
                    " bytes, but the file ends at byte " + std::to_string(size_) + " (truncated?)");
    std::size_t done = 0;
    while (done < out.size()) {
        const ssize_t n = ::pread(fd_, out.data() + done, out.size() - done, off_t(at + done));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0)
            throw Error(path_ + ": byte " + std::to_string(at + done) + ": cannot read " + what + ": " +
                        (n < 0 ? std::strerror(errno) : "the file ended"));
        done += std::size_t(n);
    }
}

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

#include "core/read_only_file.h"

#include "core/error.h"

#include <cerrno>
#include <cstring>
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

} // namespace yv

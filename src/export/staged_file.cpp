#include "export/staged_file.h"

#include "core/atomic_file.h"
#include "core/error.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <filesystem>

namespace yv {

StagedFile::StagedFile(std::string path) : path_(std::move(path)) {
    static std::atomic<unsigned> counter{0};
    for (int attempt = 0; fd_ < 0; ++attempt) {
        tmp_ = path_ + ".partial-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
        fd_ = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
        if (fd_ < 0 && (errno != EEXIST || attempt >= 100))
            throw Error(path_ + ": cannot create the temporary file " + tmp_ + ": " + errnoText(errno));
    }
}

StagedFile::~StagedFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!published_) ::unlink(tmp_.c_str());
}

void StagedFile::writeAt(std::uint64_t offset, const void* data, std::size_t n) {
    YV_CHECK(fd_ >= 0);
    const auto* p = static_cast<const std::uint8_t*>(data);
    std::size_t done = 0;
    while (done < n) {
        const ssize_t put = ::pwrite(fd_, p + done, n - done, off_t(offset + done));
        if (put < 0 && errno == EINTR) continue;
        if (put < 0)
            throw Error(path_ + ": cannot write " + tmp_ + " at byte " + std::to_string(offset + done) + ": " +
                        errnoText(errno));
        done += std::size_t(put);
    }
    size_ = std::max<std::uint64_t>(size_, offset + n);
}

void StagedFile::finish() {
    YV_CHECK(fd_ >= 0);
    // Data on disk before the name: a crash never leaves a complete-looking file.
    if (::fsync(fd_) != 0) throw Error(path_ + ": cannot fsync " + tmp_ + ": " + errnoText(errno));
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) throw Error(path_ + ": cannot close " + tmp_ + ": " + errnoText(errno));
}

void StagedFile::publish() {
    YV_CHECK(fd_ < 0 && !published_);
    if (std::rename(tmp_.c_str(), path_.c_str()) != 0)
        throw Error(path_ + ": cannot rename the finished file into place: " + errnoText(errno));
    published_ = true;
    const std::filesystem::path parent = std::filesystem::path(path_).parent_path();
    const std::string dir = parent.empty() ? "." : parent.string();
    if (Fd dirFd(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC)); dirFd.get() >= 0) fsyncDir(dirFd.get(), dir);
}

std::streamsize StagedFileBuf::xsputn(const char* s, std::streamsize n) {
    if (!error_.empty()) return 0;
    try {
        file_.writeAt(at_, s, std::size_t(n));
        at_ += std::uint64_t(n);
    } catch (const Error& e) {
        error_ = e.what();
        return 0;
    }
    return n;
}

StagedFileBuf::int_type StagedFileBuf::overflow(int_type c) {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    const char ch = traits_type::to_char_type(c);
    return xsputn(&ch, 1) == 1 ? c : traits_type::eof();
}

StagedFileBuf::pos_type StagedFileBuf::seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode which) {
    if (!(which & std::ios_base::out)) return pos_type(off_type(-1));
    const off_type base = dir == std::ios_base::beg ? 0 : dir == std::ios_base::cur ? off_type(at_) : off_type(file_.size());
    if (base + off < 0) return pos_type(off_type(-1));
    at_ = std::uint64_t(base + off);
    return pos_type(off_type(at_));
}

StagedFileBuf::pos_type StagedFileBuf::seekpos(pos_type pos, std::ios_base::openmode which) {
    return seekoff(off_type(pos), std::ios_base::beg, which);
}

} // namespace yv

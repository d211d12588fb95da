#include "core/atomic_file.h"

#include "core/error.h"
#include "core/output_path.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <filesystem>
#include <system_error>

namespace yv {

std::string errnoText(int err) { return std::generic_category().message(err); }

Fd::~Fd() {
    if (fd_ >= 0) ::close(fd_);
}

std::optional<std::vector<std::uint8_t>> readWholeFile(const std::string& path) {
    Fd fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
    if (fd.get() < 0) {
        if (errno == ENOENT) return std::nullopt;
        throw Error("cannot open " + path + ": " + errnoText(errno));
    }
    struct stat st {};
    if (::fstat(fd.get(), &st) != 0) throw Error("cannot stat " + path + ": " + errnoText(errno));
    // One byte of slack so reaching EOF at the stat size does not force a regrowth.
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(std::max<off_t>(st.st_size, 0)) + 1);
    std::size_t used = 0;
    for (;;) {
        if (used == bytes.size()) bytes.resize(bytes.size() * 2);
        const ssize_t got = ::read(fd.get(), bytes.data() + used, bytes.size() - used);
        if (got == 0) break;
        if (got < 0) {
            if (errno == EINTR) continue;
            throw Error("cannot read " + path + ": " + errnoText(errno));
        }
        used += static_cast<std::size_t>(got);
    }
    bytes.resize(used);
    return bytes;
}

void fsyncDir(int dirFd, const std::string& dir) {
    if (::fsync(dirFd) != 0 && errno != EINVAL) // EINVAL: file systems that cannot sync directories
        throw Error("cannot fsync directory " + dir + ": " + errnoText(errno));
}

namespace {

/// Refuses to publish over what is not a regular file (core/output_path.h):
/// the commands check their outputs before any work, and this holds for every
/// writer, and for a target that changed while the file was being written.
void checkTarget(const std::string& path) {
    if (const std::string kind = nonRegularKind(path); !kind.empty())
        throw Error("cannot write " + path + ": it is " + kind + ", not a regular file: refusing to replace it");
}

} // namespace

PendingFile::PendingFile(std::string path, int dirFd) : path_(std::move(path)), dirFd_(dirFd) {
    checkTarget(path_); // before the temporary is made beside it (in /dev, say)
    static std::atomic<unsigned> counter{0};
    const std::filesystem::path parent = std::filesystem::path(path_).parent_path();
    dir_ = parent.empty() ? "." : parent.string();
    for (int attempt = 0; fd_ < 0; ++attempt) {
        tmp_ = path_ + ".partial-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
        fd_ = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd_ < 0 && (errno != EEXIST || attempt >= 100)) fail("create", errno);
    }
    if (dirFd_ < 0) {
        // A directory that cannot be opened for reading cannot be synced
        // either: the rename is then as durable as the file system makes it.
        dirFd_ = ::open(dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
        ownsDirFd_ = dirFd_ >= 0;
    }
}

PendingFile::~PendingFile() {
    if (fd_ >= 0) ::close(fd_);
    // Removing the temporary on every failure keeps half-written files from piling up.
    if (!published_) ::unlink(tmp_.c_str());
    if (ownsDirFd_) ::close(dirFd_);
}

void PendingFile::fail(const char* step, int err) const {
    throw Error("cannot write " + path_ + ": " + step + " " + tmp_ + ": " + errnoText(err));
}

void PendingFile::writeAt(std::uint64_t offset, const void* data, std::size_t n) {
    YV_CHECK(fd_ >= 0);
    const auto* p = static_cast<const std::uint8_t*>(data);
    for (std::size_t done = 0; done < n;) {
        const ssize_t put = ::pwrite(fd_, p + done, n - done, off_t(offset + done));
        if (put < 0 && errno == EINTR) continue;
        if (put < 0) fail("write", errno);
        if (put == 0) fail("write", EIO);
        done += std::size_t(put);
    }
    size_ = std::max<std::uint64_t>(size_, offset + n);
}

void PendingFile::sync() {
    YV_CHECK(fd_ >= 0);
    // Data on disk before the name: a crash never leaves a complete-looking file.
    if (::fsync(fd_) != 0) fail("fsync", errno);
    if (::close(std::exchange(fd_, -1)) != 0) fail("close", errno);
}

void PendingFile::publish() {
    YV_CHECK(!published_);
    if (fd_ >= 0) sync();
    checkTarget(path_);
    if (::rename(tmp_.c_str(), path_.c_str()) != 0) fail("rename", errno);
    published_ = true;
    // The rename itself is durable only once the directory is synced.
    if (dirFd_ >= 0) fsyncDir(dirFd_, dir_);
}

void writeFileAtomically(const std::string& path, std::span<const std::span<const std::uint8_t>> parts, int dirFd) {
    PendingFile file(path, dirFd);
    for (std::span<const std::uint8_t> part : parts) file.append(part);
    file.publish();
}

void writeFileAtomically(const std::string& path, std::span<const std::uint8_t> bytes) {
    const std::span<const std::uint8_t> parts[] = {bytes};
    writeFileAtomically(path, parts);
}

} // namespace yv

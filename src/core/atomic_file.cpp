#include "core/atomic_file.h"

#include "core/error.h"

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

void writeAtomically(const std::string& dir, int dirFd, const std::string& name,
                     std::span<const std::span<const std::uint8_t>> parts) {
    static std::atomic<unsigned> counter{0};
    const std::string path = (std::filesystem::path(dir) / name).string();
    std::string tmp;
    int raw = -1;
    for (int attempt = 0; raw < 0; ++attempt) {
        tmp = path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
        raw = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (raw < 0 && (errno != EEXIST || attempt >= 100))
            throw Error("cannot write " + path + ": cannot create temporary file " + tmp + ": " + errnoText(errno));
    }
    Fd fd(raw);
    // Removing the temporary on every failure keeps half-written files from piling up.
    const auto abandon = [&](const char* step, int err) {
        if (fd.get() >= 0) ::close(fd.release());
        ::unlink(tmp.c_str());
        return Error("cannot write " + path + ": " + step + " " + tmp + ": " + errnoText(err));
    };
    for (std::span<const std::uint8_t> part : parts) {
        std::size_t done = 0;
        while (done < part.size()) {
            const ssize_t put = ::write(fd.get(), part.data() + done, part.size() - done);
            if (put < 0 && errno == EINTR) continue;
            if (put < 0) throw abandon("write", errno);
            done += static_cast<std::size_t>(put);
        }
    }
    if (::fsync(fd.get()) != 0) throw abandon("fsync", errno);
    if (::close(fd.release()) != 0) throw abandon("close", errno);
    if (::rename(tmp.c_str(), path.c_str()) != 0) throw abandon("rename", errno);
    fsyncDir(dirFd, dir);
}

void writeFileAtomically(const std::string& path, std::span<const std::uint8_t> bytes) {
    const std::filesystem::path p(path);
    const std::string dir = p.has_parent_path() ? p.parent_path().string() : std::string(".");
    Fd dirFd(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    if (dirFd.get() < 0) throw Error("cannot write " + path + ": cannot open directory " + dir + ": " + errnoText(errno));
    const std::span<const std::uint8_t> parts[] = {bytes};
    writeAtomically(dir, dirFd.get(), p.filename().string(), parts);
}

} // namespace yv

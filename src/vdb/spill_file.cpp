#include "vdb/spill_file.h"

#include "core/error.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>

namespace yv {
namespace {

int openUnnamed(const std::string& dir, const std::string& where) {
#ifdef O_TMPFILE
    const int fd = ::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
    if (fd >= 0) return fd;
    // Some file systems have no unnamed files: fall back to a name removed at once.
    if (errno != EOPNOTSUPP && errno != EISDIR && errno != EINVAL && errno != ENOENT)
        throw Error("cannot create " + where + ": " + errnoText(errno));
#endif
    std::string name = (std::filesystem::path(dir) / ".yarnvox-spill-XXXXXX").string();
    const int named = ::mkostemp(name.data(), O_CLOEXEC);
    if (named < 0) throw Error("cannot create " + where + ": " + errnoText(errno));
    ::unlink(name.c_str());
    return named;
}

} // namespace

void writeAllAt(int fd, std::span<const std::uint8_t> bytes, std::uint64_t offset, const std::string& what) {
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::pwrite(fd, bytes.data() + done, bytes.size() - done, off_t(offset + done));
        if (n < 0) {
            if (errno == EINTR) continue;
            throw Error(what + ": " + errnoText(errno));
        }
        if (n == 0) throw Error(what + ": the write made no progress");
        done += std::size_t(n);
    }
}

SpillFile::SpillFile(const std::string& dir, std::string purpose)
    : where_(std::move(purpose) + " (an unnamed temporary file in " + (dir.empty() ? "." : dir) + ")"),
      fd_(openUnnamed(dir.empty() ? "." : dir, where_)) {}

std::uint64_t SpillFile::append(std::span<const std::uint8_t> bytes) {
    const std::uint64_t at = end_.fetch_add(bytes.size());
    writeAllAt(fd_.get(), bytes, at, "cannot write " + where_);
    return at;
}

void SpillFile::writeAt(std::uint64_t offset, std::span<const std::uint8_t> bytes) {
    YV_CHECK(offset + bytes.size() <= end_.load());
    writeAllAt(fd_.get(), bytes, offset, "cannot write " + where_);
}

void SpillFile::read(std::uint64_t offset, std::span<std::uint8_t> out) const {
    std::size_t done = 0;
    while (done < out.size()) {
        const ssize_t n = ::pread(fd_.get(), out.data() + done, out.size() - done, off_t(offset + done));
        if (n < 0) {
            if (errno == EINTR) continue;
            throw Error("cannot read " + where_ + ": " + errnoText(errno));
        }
        if (n == 0) throw Error("cannot read " + where_ + ": it ends early");
        done += std::size_t(n);
    }
}

} // namespace yv

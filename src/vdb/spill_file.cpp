#include "vdb/spill_file.h"

#include "core/environment_count.h"
#include "core/error.h"
#include "core/huge_pages.h"
#include "core/process_memory.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
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

SpillFile::SpillFile(const std::string& dir, std::string purpose, std::uint64_t memoryBytes)
    : where_(std::move(purpose) + " (an unnamed temporary file in " + (dir.empty() ? "." : dir) + ")"),
      fd_(openUnnamed(dir.empty() ? "." : dir, where_)) {
    if (memoryBytes == 0) return;
    // Address space only: a page is taken when first written (MAP_NORESERVE:
    // not counted against the commit limit before that), 2 MiB at a time
    // where the kernel offers huge pages. Where the mapping is refused, all
    // of it goes to the file.
    const std::uint64_t rounded = (memoryBytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
    void* p = ::mmap(nullptr, rounded, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (p == MAP_FAILED) return;
    ::madvise(p, rounded, MADV_HUGEPAGE); // advice only
    memory_ = static_cast<std::uint8_t*>(p);
    memoryBytes_ = rounded;
}

SpillFile::~SpillFile() {
    if (memory_) ::munmap(memory_, memoryBytes_);
}

std::uint64_t SpillFile::append(std::span<const std::uint8_t> bytes) {
    const std::uint64_t at = end_.fetch_add(bytes.size());
    writeAt(at, bytes);
    return at;
}

std::size_t SpillFile::inMemory(std::uint64_t offset, std::size_t bytes) const {
    return offset < memoryBytes_ ? std::size_t(std::min<std::uint64_t>(bytes, memoryBytes_ - offset)) : 0;
}

void SpillFile::writeAt(std::uint64_t offset, std::span<const std::uint8_t> bytes) {
    YV_CHECK(offset + bytes.size() <= end_.load());
    const std::size_t held = inMemory(offset, bytes.size());
    if (held > 0) std::memcpy(memory_ + offset, bytes.data(), held);
    if (held < bytes.size())
        writeAllAt(fd_.get(), bytes.subspan(held), offset + held - memoryBytes_, "cannot write " + where_);
}

void SpillFile::read(std::uint64_t offset, std::span<std::uint8_t> out) const {
    const std::size_t held = inMemory(offset, out.size());
    if (held > 0) std::memcpy(out.data(), memory_ + offset, held);
    out = out.subspan(held);
    offset += held;
    if (out.empty()) return;
    std::size_t done = 0;
    const std::uint64_t at = offset - memoryBytes_;
    while (done < out.size()) {
        const ssize_t n = ::pread(fd_.get(), out.data() + done, out.size() - done, off_t(at + done));
        if (n < 0) {
            if (errno == EINTR) continue;
            throw Error("cannot read " + where_ + ": " + errnoText(errno));
        }
        if (n == 0) throw Error("cannot read " + where_ + ": it ends early");
        done += std::size_t(n);
    }
}

std::uint64_t spillMemoryBytes() {
    constexpr std::uint64_t kMB = std::uint64_t(1) << 20;
    const char* what = "MB of memory for the .vdb writer's scratch space";
    if (const std::optional<long> mb = countFromEnvironment("YV_SPILL_MEMORY_MB", 0, 1l << 30, what))
        return std::uint64_t(*mb) * kMB;
    return std::min(physicalMemoryBytes() / 4, availableMemoryBytes() / 2);
}

} // namespace yv

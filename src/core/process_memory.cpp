#include "core/process_memory.h"

#include <cstdio>
#include <cstring>
#include <unistd.h>

namespace yv {
namespace {

/// Field `field` (in KiB) of a /proc file of "Name: value kB" lines; 0 if absent.
std::uint64_t readKiB(const char* path, const char* field) {
    FILE* f = std::fopen(path, "r");
    if (!f) return 0;
    char line[256];
    std::uint64_t kib = 0;
    const std::size_t len = std::strlen(field);
    while (std::fgets(line, sizeof line, f))
        if (std::strncmp(line, field, len) == 0 && line[len] == ':') {
            unsigned long long v = 0;
            if (std::sscanf(line + len + 1, "%llu", &v) == 1) kib = v;
            break;
        }
    std::fclose(f);
    return kib * 1024;
}

} // namespace

std::uint64_t peakResidentBytes() { return readKiB("/proc/self/status", "VmHWM"); }
std::uint64_t currentResidentBytes() { return readKiB("/proc/self/status", "VmRSS"); }

std::uint64_t physicalMemoryBytes() {
    const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGE_SIZE);
    return pages > 0 && pageSize > 0 ? std::uint64_t(pages) * std::uint64_t(pageSize) : (std::uint64_t(8) << 30);
}

std::uint64_t availableMemoryBytes() {
    const std::uint64_t available = readKiB("/proc/meminfo", "MemAvailable");
    return available > 0 ? available : physicalMemoryBytes();
}

} // namespace yv

#include "core/process_memory.h"

#include <cstdio>
#include <cstring>
#include <unistd.h>

namespace yv {
namespace {

std::uint64_t readStatusKiB(const char* field) {
    FILE* f = std::fopen("/proc/self/status", "r");
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

std::uint64_t peakResidentBytes() { return readStatusKiB("VmHWM"); }
std::uint64_t currentResidentBytes() { return readStatusKiB("VmRSS"); }

std::uint64_t physicalMemoryBytes() {
    const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGE_SIZE);
    return pages > 0 && pageSize > 0 ? std::uint64_t(pages) * std::uint64_t(pageSize) : (std::uint64_t(8) << 30);
}

} // namespace yv

#include "core/huge_pages.h"

#include <sys/mman.h>

#include <cstdint>

namespace yv {

void* allocateHugePages(std::size_t bytes) {
    if (bytes < kHugePageBytes) return ::operator new(bytes == 0 ? 1 : bytes);
    const std::size_t rounded = (bytes + kHugePageBytes - 1) & ~(kHugePageBytes - 1);
    // Mapped one huge page longer, then trimmed to a 2 MiB boundary: the
    // kernel backs only aligned 2 MiB ranges with huge pages.
    void* mapped = ::mmap(nullptr, rounded + kHugePageBytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (mapped == MAP_FAILED) throw std::bad_alloc();
    const auto start = reinterpret_cast<std::uintptr_t>(mapped);
    const std::uintptr_t aligned = (start + kHugePageBytes - 1) & ~std::uintptr_t(kHugePageBytes - 1);
    if (aligned > start) ::munmap(mapped, aligned - start);
    if (const std::size_t tail = (start + rounded + kHugePageBytes) - (aligned + rounded); tail > 0)
        ::munmap(reinterpret_cast<void*>(aligned + rounded), tail);
    // Advice only: where huge pages are off, the pages are small ones.
    ::madvise(reinterpret_cast<void*>(aligned), rounded, MADV_HUGEPAGE);
    return reinterpret_cast<void*>(aligned);
}

void freeHugePages(void* p, std::size_t bytes) noexcept {
    if (!p) return;
    if (bytes < kHugePageBytes) {
        ::operator delete(p);
        return;
    }
    ::munmap(p, (bytes + kHugePageBytes - 1) & ~(kHugePageBytes - 1));
}

} // namespace yv

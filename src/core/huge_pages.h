// Memory for large buffers that are filled once at full speed: the region's
// packed bricks that the host copies out of the GPU's readback buffer.
// Fresh 4 KiB pages cost a fault each (the copy into them ran at a third of
// the speed of a copy into pages already touched); these buffers ask the
// kernel for 2 MiB pages where it offers them (transparent huge pages in
// "madvise" or "always" mode), one fault per 512 small pages. Where it does
// not, they are ordinary pages.
#pragma once

#include <cstddef>
#include <new>

namespace yv {

/// `bytes` of memory, 2 MiB aligned and advised for huge pages when at least
/// kHugePageBytes, else from operator new. Throws std::bad_alloc.
void* allocateHugePages(std::size_t bytes);
/// Frees what allocateHugePages(bytes) returned (the same `bytes`).
void freeHugePages(void* p, std::size_t bytes) noexcept;
inline constexpr std::size_t kHugePageBytes = std::size_t(2) << 20;

/// An allocator over allocateHugePages, for vectors of trivial records.
template <typename T>
struct HugePageAllocator {
    using value_type = T;
    HugePageAllocator() = default;
    template <typename U>
    HugePageAllocator(const HugePageAllocator<U>&) noexcept {}
    T* allocate(std::size_t n) {
        if (n > std::size_t(-1) / sizeof(T)) throw std::bad_alloc();
        return static_cast<T*>(allocateHugePages(n * sizeof(T)));
    }
    void deallocate(T* p, std::size_t n) noexcept { freeHugePages(p, n * sizeof(T)); }
    template <typename U>
    bool operator==(const HugePageAllocator<U>&) const noexcept { return true; }
};

} // namespace yv

// libFuzzer target: the PNG cross-section reader (src/garment/cross_section.cpp).
// The reader takes a path: each input goes through an in-memory file.
#include "core/error.h"
#include "garment/cross_section.h"

#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const int fd = memfd_create("fuzz.png", 0);
    if (fd < 0) __builtin_trap();
    for (std::size_t done = 0; done < size;) {
        const ssize_t n = write(fd, data + done, size - done);
        if (n <= 0) __builtin_trap();
        done += static_cast<std::size_t>(n);
    }
    try {
        (void)yv::loadCrossSectionPng("/proc/self/fd/" + std::to_string(fd));
    } catch (const yv::Error&) {
    }
    close(fd);
    return 0;
}

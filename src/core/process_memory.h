// Host memory: this process's, read from /proc, and the machine's.
#pragma once

#include <cstdint>

namespace yv {

/// Peak resident set size of this process so far (VmHWM), bytes; 0 if unknown.
std::uint64_t peakResidentBytes();
/// Current resident set size (VmRSS), bytes; 0 if unknown.
std::uint64_t currentResidentBytes();
/// Physical memory of the machine, bytes; 8 GiB where the system cannot tell.
std::uint64_t physicalMemoryBytes();
/// Memory the kernel can give without swapping now (MemAvailable), bytes;
/// physicalMemoryBytes() where the system cannot tell.
std::uint64_t availableMemoryBytes();

} // namespace yv

// Host memory of this process, read from /proc.
#pragma once

#include <cstdint>

namespace yv {

/// Peak resident set size of this process so far (VmHWM), bytes; 0 if unknown.
std::uint64_t peakResidentBytes();
/// Current resident set size (VmRSS), bytes; 0 if unknown.
std::uint64_t currentResidentBytes();

} // namespace yv

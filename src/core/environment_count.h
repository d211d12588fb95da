// Counts read from environment variables (YV_WRITER_THREADS, YV_PIPELINE_REGIONS):
// settings a benchmark changes without a rebuild, refused in one line when
// they are not a whole number in range.
#pragma once

#include <optional>
#include <string>

namespace yv {

/// The whole number environment variable `name` holds, or nothing where it
/// is unset. Throws yv::Error "NAME=TEXT: not a count of WHAT (MIN to MAX)"
/// where it holds anything but a whole number from `min` to `max`.
std::optional<long> countFromEnvironment(const char* name, long min, long max, const std::string& what);

} // namespace yv

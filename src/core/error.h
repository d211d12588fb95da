// Errors that carry where and why, so the CLI can print one line and exit non-zero.
#pragma once

#include <stdexcept>
#include <string>

namespace yv {

/// A user-facing failure: bad input, a missing file, an unusable GPU. The
/// message names the place (file, byte offset, yarn index) and what to do.
class Error : public std::runtime_error {
  public:
    explicit Error(const std::string& what) : std::runtime_error(what) {}
};

/// A broken invariant inside yarnvox itself (a bug, not bad input).
#define YV_CHECK(cond)                                                              \
    do {                                                                            \
        if (!(cond))                                                                \
            throw ::yv::Error(std::string(__FILE__) + ":" + std::to_string(__LINE__) + \
                              ": internal check failed: " #cond);                  \
    } while (0)

} // namespace yv

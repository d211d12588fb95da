// Command-line number checks shared by the subcommands: every number is
// checked where it is parsed, and the message repeats what was typed.
#pragma once

#include "core/world_units.h"

#include <CLI/CLI.hpp>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <string>
#include <type_traits>

namespace yv {

namespace detail {
/// The whole text as a double; false when it is not one number ("1.5x", "").
inline bool parseWholeNumber(const std::string& text, double& v) {
    char* end = nullptr;
    v = std::strtod(text.c_str(), &end);
    return !text.empty() && end == text.c_str() + text.size();
}
} // namespace detail

/// A world-unit length: finite, positive, within [kMinLength, kMaxLength].
/// CLI11's PositiveNumber lets nan through (nan <= 0 is false).
inline CLI::Validator worldLength() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            double v = 0.0;
            if (!detail::parseWholeNumber(text, v)) return "'" + text + "' is not a number";
            const std::string problem = lengthProblem(v);
            return problem.empty() ? std::string() : "'" + text + "': " + problem;
        },
        "LENGTH", "world-unit length");
}

/// A finite number of magnitude at most `limit`.
inline CLI::Validator finiteNumber(double limit) {
    return CLI::Validator(
        [limit](std::string& text) -> std::string {
            double v = 0.0;
            if (!detail::parseWholeNumber(text, v)) return "'" + text + "' is not a number";
            if (!std::isfinite(v)) return "'" + text + "' is not a finite number";
            if (std::abs(v) > limit) return "'" + text + "' is beyond " + numberText(limit) + " in magnitude";
            return {};
        },
        "NUMBER", "finite number");
}

/// A finite number in [lo, hi]. CLI11's Range lets nan through (nan < lo is
/// false): an isosurface at nan drew nothing, with exit 0.
inline CLI::Validator finiteRange(double lo, double hi) {
    return CLI::Validator(
        [lo, hi](std::string& text) -> std::string {
            double v = 0.0;
            if (!detail::parseWholeNumber(text, v)) return "'" + text + "' is not a number";
            if (!std::isfinite(v)) return "'" + text + "' is not a finite number";
            if (v < lo || v > hi) return "'" + text + "' is not in [" + numberText(lo) + ", " + numberText(hi) + "]";
            return {};
        },
        "NUMBER in [" + numberText(lo) + ", " + numberText(hi) + "]", "finite number");
}

/// A whole number in [lo, hi] (a count, an index, a level), in digits. CLI11's
/// Range called 1.5 "not in range" and its conversion "could not convert";
/// this says which it is: not a number, not a whole number, another spelling
/// of one ("1e3", which CLI11 cannot convert), or outside the range.
template <class T>
CLI::Validator wholeNumber(T lo, T hi) {
    static_assert(std::is_integral_v<T>);
    return CLI::Validator(
        [lo, hi](std::string& text) -> std::string {
            double v = 0.0;
            if (!detail::parseWholeNumber(text, v)) return "'" + text + "' is not a number";
            if (!std::isfinite(v) || v != std::floor(v)) return "'" + text + "' is not a whole number";
            const std::string outside =
                "'" + text + "' is not in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
            if (v < double(lo) || v > double(hi)) return outside; // also -1 for an unsigned option
            // The digits read exactly: a double rounds beyond 2^53.
            errno = 0;
            char* end = nullptr;
            const auto n = std::is_signed_v<T> ? T(std::strtoll(text.c_str(), &end, 10)) : T(std::strtoull(text.c_str(), &end, 10));
            if (end != text.c_str() + text.size()) return "'" + text + "': write the whole number in digits";
            return errno == ERANGE || n < lo || n > hi ? outside : std::string();
        },
        "whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]", "whole number");
}

} // namespace yv

// Command-line number checks shared by the subcommands: every number is
// checked where it is parsed, and the message repeats what was typed.
#pragma once

#include "core/world_units.h"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdlib>
#include <string>

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

} // namespace yv

#include "core/environment_count.h"

#include "core/error.h"

#include <cstdlib>

namespace yv {

std::optional<long> countFromEnvironment(const char* name, long min, long max, const std::string& what) {
    const char* text = std::getenv(name);
    if (!text) return std::nullopt;
    char* end = nullptr;
    const long n = std::strtol(text, &end, 10);
    if (end == text || *end != '\0' || n < min || n > max)
        throw Error(std::string(name) + "=" + text + ": not a count of " + what + " (" + std::to_string(min) + " to " +
                    std::to_string(max) + ")");
    return n;
}

} // namespace yv

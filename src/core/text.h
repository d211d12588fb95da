// Small formatting helpers for messages and text files.
#pragma once

#include <glm/vec3.hpp>

#include <cinttypes>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace yv {

/// "0x" and 16 hex digits.
inline std::string hex64(std::uint64_t v) {
    char s[24];
    std::snprintf(s, sizeof s, "0x%016" PRIx64, v);
    return s;
}

/// A name read from a file, fit for a one-line message: at most 64
/// characters ("..." where cut), anything but printable ASCII as '?'. A
/// damaged name may be 64 KiB of any bytes.
inline std::string shownName(const std::string& name) {
    std::string out = name.size() <= 64 ? name : name.substr(0, 61) + "...";
    for (char& c : out)
        if (c < 0x20 || c > 0x7e) c = '?';
    return out;
}

/// "(x, y, z)", for voxel and brick coordinates in messages.
inline std::string coordText(glm::ivec3 v) {
    return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
}

/// `count` comma-separated finite numbers (e.g. "0,0,0,64,64,32" for a box),
/// or nullopt when `text` is anything else; the caller says what was expected.
inline std::optional<std::vector<double>> parseNumberList(const std::string& text, std::size_t count) {
    std::vector<double> numbers;
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, ',');) {
        char* end = nullptr;
        const double x = std::strtod(item.c_str(), &end);
        if (item.empty() || end != item.c_str() + item.size() || !std::isfinite(x) || numbers.size() == count)
            return std::nullopt;
        numbers.push_back(x);
    }
    if (numbers.size() != count) return std::nullopt;
    return numbers;
}

} // namespace yv

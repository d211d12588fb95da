// Small formatting helpers for messages and text files.
#pragma once

#include <glm/vec3.hpp>

#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <string>

namespace yv {

/// "0x" and 16 hex digits.
inline std::string hex64(std::uint64_t v) {
    char s[24];
    std::snprintf(s, sizeof s, "0x%016" PRIx64, v);
    return s;
}

/// "(x, y, z)", for voxel and brick coordinates in messages.
inline std::string coordText(glm::ivec3 v) {
    return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
}

} // namespace yv

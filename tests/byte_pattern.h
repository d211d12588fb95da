// Test bytes that differ from one offset to the next and from one seed to
// another: a copy or a read that lands a byte in the wrong place shows.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace yv::test {

inline std::vector<std::uint8_t> bytePattern(std::size_t bytes, std::uint32_t seed) {
    std::vector<std::uint8_t> v(bytes);
    std::uint32_t x = seed * 2654435761u + 1u;
    for (std::uint8_t& b : v) {
        x = x * 1664525u + 1013904223u;
        b = std::uint8_t(x >> 24);
    }
    return v;
}

} // namespace yv::test

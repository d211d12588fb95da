// A .vdb's bytes without the 36-character UUID OpenVDB's format puts in
// every file's header (after the magic number, three version numbers and
// the offsets flag): two writes of the same volume compare equal.
#pragma once

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

namespace yv::test {

inline std::vector<std::uint8_t> vdbBytesWithoutUuid(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    REQUIRE(bytes.size() > 57);
    std::fill(bytes.begin() + 21, bytes.begin() + 57, 0);
    return bytes;
}

} // namespace yv::test

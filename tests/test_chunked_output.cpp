// The output written in aligned chunks side by side (vdb/chunked_output.h):
// every byte where the caller put it, the file exactly its size, whether the
// chunks went past the page cache or not.
#include "core/error.h"
#include "vdb/chunked_output.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <vector>

using namespace yv;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) { return yv::test::processScratchDir("yv_chunked_test") / name; }

/// A byte that depends on its offset, so a chunk written at the wrong place shows.
std::uint8_t patternByte(std::uint64_t at) { return std::uint8_t((at * 2654435761u) >> 13); }

std::vector<std::uint8_t> fileBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

} // namespace

TEST_CASE("A chunked output holds every byte where the fill put it, and no more", "[vdb][chunked]") {
    const std::uint64_t chunk = 2 * ChunkedOutput::kAlignment;
    // Sizes inside one page, at a page, past one, at and past a chunk, many chunks.
    for (std::uint64_t size : {std::uint64_t(1), std::uint64_t(4095), std::uint64_t(4096), std::uint64_t(4097),
                               chunk, chunk + 1, 5 * chunk + 123}) {
        INFO("size " << size);
        const fs::path path = scratch("pattern.bin");
        fs::remove(path);
        std::vector<int> filled(std::size_t((size + chunk - 1) / chunk), 0);
        {
            ChunkedOutput out(path.string(), "test output", chunk);
            out.write(size, [&](std::uint64_t at, std::span<std::uint8_t> bytes) {
                CHECK(at % chunk == 0);
                CHECK(bytes.size() == std::min(chunk, size - at));
                ++filled[std::size_t(at / chunk)];
                for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = patternByte(at + i);
            });
            INFO("direct writes: " << out.direct());
        }
        for (int n : filled) CHECK(n == 1);
        REQUIRE(fs::file_size(path) == size);
        const std::vector<std::uint8_t> bytes = fileBytes(path);
        std::size_t wrong = 0;
        for (std::uint64_t i = 0; i < size; ++i) wrong += bytes[std::size_t(i)] != patternByte(i);
        CHECK(wrong == 0);
        fs::remove(path);
    }
}

TEST_CASE("A chunked output refuses a name that exists, and a failing fill fails the write", "[vdb][chunked]") {
    const fs::path path = scratch("exists.bin");
    std::ofstream(path) << "kept";
    try {
        ChunkedOutput out(path.string(), "test output");
        FAIL("an existing file was opened");
    } catch (const Error& e) {
        CHECK(std::string(e.what()).find("test output: cannot create it") != std::string::npos);
    }
    CHECK(fileBytes(path).size() == 4); // untouched
    fs::remove(path);

    ChunkedOutput out(path.string(), "test output", ChunkedOutput::kAlignment);
    CHECK_THROWS_WITH(out.write(10 * ChunkedOutput::kAlignment,
                                [](std::uint64_t at, std::span<std::uint8_t> bytes) {
                                    if (at == 7 * ChunkedOutput::kAlignment) throw Error("no such record");
                                    std::fill(bytes.begin(), bytes.end(), std::uint8_t(1));
                                }),
                      "no such record");
    fs::remove(path);
}

// A large copy split over threads of its own (core/parallel_copy.h): every
// byte lands where memcpy would put it, whatever the size, and callers on
// several threads at once (one gets the threads, the others copy alone)
// each get their own bytes.
#include "core/parallel_copy.h"
#include "byte_pattern.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <thread>
#include <vector>

using namespace yv;
using yv::test::bytePattern;

TEST_CASE("copyInParallel copies every byte of small and large copies and of odd sizes", "[parallel_copy]") {
    // The copies of 4 MiB and more go to the helpers: there must be one, even on two cores.
    REQUIRE(copyHelperThreads() >= 1);
    for (std::size_t bytes : {std::size_t(0), std::size_t(1), std::size_t(4095), std::size_t(4) << 20,
                              (std::size_t(4) << 20) + 1, (std::size_t(37) << 20) + 12345}) {
        const std::vector<std::uint8_t> from = bytePattern(bytes, 7);
        // Guard bytes on both sides: nothing outside the range is written.
        std::vector<std::uint8_t> to(bytes + 64, 0xAB);
        copyInParallel(to.data() + 32, from.data(), bytes);
        INFO("bytes " << bytes);
        CHECK(std::equal(from.begin(), from.end(), to.begin() + 32));
        CHECK(std::all_of(to.begin(), to.begin() + 32, [](std::uint8_t b) { return b == 0xAB; }));
        CHECK(std::all_of(to.end() - 32, to.end(), [](std::uint8_t b) { return b == 0xAB; }));
    }
}

TEST_CASE("copyInParallel from several threads at once gives each caller its own bytes", "[parallel_copy]") {
    constexpr int kCallers = 4;
    constexpr std::size_t kBytes = (std::size_t(24) << 20) + 7;
    std::vector<std::vector<std::uint8_t>> from, to;
    for (int c = 0; c < kCallers; ++c) {
        from.push_back(bytePattern(kBytes, std::uint32_t(c + 1)));
        to.emplace_back(kBytes, 0);
    }
    std::vector<std::thread> callers;
    for (int c = 0; c < kCallers; ++c)
        callers.emplace_back([&, c] {
            for (int round = 0; round < 5; ++round) copyInParallel(to[std::size_t(c)].data(), from[std::size_t(c)].data(), kBytes);
        });
    for (std::thread& t : callers) t.join();
    for (int c = 0; c < kCallers; ++c) {
        INFO("caller " << c);
        CHECK(to[std::size_t(c)] == from[std::size_t(c)]);
    }
}

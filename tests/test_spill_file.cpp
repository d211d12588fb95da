// The .vdb writer's scratch space (vdb/spill_file.h): its first part in
// memory, the rest in a file. Whatever lands on either side or across the
// line between them, appended or reserved and filled in pieces from several
// threads, reads back byte for byte.
#include "core/error.h"
#include "core/process_memory.h"
#include "vdb/spill_file.h"
#include "byte_pattern.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <thread>
#include <vector>

namespace fs = std::filesystem;
using namespace yv;
using yv::test::bytePattern;

namespace {

fs::path scratchDir() { return yv::test::processScratchDir("yv_spill_test"); }

constexpr std::uint64_t kMiB = std::uint64_t(1) << 20;

} // namespace

TEST_CASE("The scratch space reads back what was appended, in memory, in the file and across both", "[vdb][spill]") {
    for (std::uint64_t memory : {std::uint64_t(0), 3 * kMiB, 64 * kMiB}) {
        INFO("memory part asked for: " << memory);
        SpillFile spill(scratchDir().string(), "the test's scratch space", memory);
        // Four threads appending pieces of odd sizes, about 9 MiB in all:
        // with 3 MiB asked (4 MiB given, whole 2 MiB pages), pieces land on
        // both sides and one across the line.
        struct Piece {
            std::uint64_t at;
            std::vector<std::uint8_t> bytes;
        };
        std::vector<std::vector<Piece>> pieces(4);
        std::vector<std::thread> threads;
        for (std::uint32_t t = 0; t < 4; ++t)
            threads.emplace_back([&, t] {
                for (std::uint32_t i = 0; i < 40; ++i) {
                    std::vector<std::uint8_t> bytes = bytePattern(20000 + 1237 * i + 3 * t + (i % 7) * 40000, t * 100 + i);
                    const std::uint64_t at = spill.append(bytes);
                    pieces[t].push_back({at, std::move(bytes)});
                }
            });
        for (std::thread& t : threads) t.join();
        std::vector<std::uint8_t> whole(spill.size());
        std::uint64_t total = 0;
        for (const std::vector<Piece>& list : pieces)
            for (const Piece& p : list) {
                std::vector<std::uint8_t> back(p.bytes.size());
                spill.read(p.at, back);
                CHECK(back == p.bytes);
                std::copy(p.bytes.begin(), p.bytes.end(), whole.begin() + std::ptrdiff_t(p.at));
                total += p.bytes.size();
            }
        REQUIRE(total == spill.size());
        // One read of everything, and reads of odd lengths from odd places.
        std::vector<std::uint8_t> all(spill.size());
        spill.read(0, all);
        CHECK(all == whole);
        for (std::uint64_t at = 1; at + 300001 < spill.size(); at += 700001) {
            std::vector<std::uint8_t> part(300001);
            spill.read(at, part);
            CHECK(std::equal(part.begin(), part.end(), whole.begin() + std::ptrdiff_t(at)));
        }
        const std::uint64_t held = memory == 0 ? 0 : memory == 3 * kMiB ? 4 * kMiB : spill.size();
        CHECK(spill.bytesInMemory() == held);
    }
}

TEST_CASE("The scratch space takes a reserved range filled in pieces from several threads across the line",
          "[vdb][spill]") {
    SpillFile spill(scratchDir().string(), "the test's scratch space", 2 * kMiB);
    const std::uint64_t before = spill.append(bytePattern(kMiB + 17, 1));
    const std::vector<std::uint8_t> bytes = bytePattern(3 * kMiB + 5, 2);
    const std::uint64_t at = spill.reserve(bytes.size());
    REQUIRE(at == kMiB + 17);
    REQUIRE(at < 2 * kMiB); // the range starts in memory and ends in the file
    std::vector<std::thread> threads;
    const std::size_t piece = bytes.size() / 3 + 1;
    for (std::size_t from = 0; from < bytes.size(); from += piece)
        threads.emplace_back([&, from] {
            const std::size_t n = std::min(piece, bytes.size() - from);
            spill.writeAt(at + from, std::span(bytes).subspan(from, n));
        });
    for (std::thread& t : threads) t.join();
    std::vector<std::uint8_t> back(bytes.size());
    spill.read(at, back);
    CHECK(back == bytes);
    std::vector<std::uint8_t> first(kMiB + 17);
    spill.read(before, first);
    CHECK(first == bytePattern(kMiB + 17, 1));
    CHECK(spill.bytesInMemory() == 2 * kMiB);
    CHECK(spill.size() == 4 * kMiB + 22);
}

TEST_CASE("YV_SPILL_MEMORY_MB sets the scratch space's memory part and a bad value says so", "[vdb][spill]") {
    ::setenv("YV_SPILL_MEMORY_MB", "5", 1);
    CHECK(spillMemoryBytes() == 5 * kMiB);
    ::setenv("YV_SPILL_MEMORY_MB", "0", 1);
    CHECK(spillMemoryBytes() == 0);
    for (const char* bad : {"-1", "2G", "", "1e3"}) {
        ::setenv("YV_SPILL_MEMORY_MB", bad, 1);
        CHECK_THROWS_WITH(spillMemoryBytes(), Catch::Contains(std::string("YV_SPILL_MEMORY_MB=") + bad +
                                                              ": not a count of MB of memory"));
    }
    ::unsetenv("YV_SPILL_MEMORY_MB");
    // By default: some memory, and never more than a quarter of the machine's.
    CHECK(spillMemoryBytes() > 0);
    CHECK(spillMemoryBytes() <= physicalMemoryBytes() / 4);
}

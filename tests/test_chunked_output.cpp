// The output written in aligned chunks side by side (vdb/chunked_output.h):
// every byte where the caller put it, the file exactly its size, whether the
// chunks went past the page cache or fell back to it.
#include "core/atomic_file.h"
#include "core/error.h"
#include "vdb/chunked_output.h"
#include "run_cli.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>
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

/// Fills with the pattern, and counts each chunk's calls in its own slot
/// (the fill runs on several threads; Catch2's checks wait until after).
struct PatternFill {
    std::uint64_t chunk;
    std::vector<std::atomic<int>> calls;
    std::vector<std::uint64_t> sizes;
    PatternFill(std::uint64_t size, std::uint64_t chunkBytes)
        : chunk(chunkBytes), calls((size + chunkBytes - 1) / chunkBytes), sizes(calls.size()) {}
    void operator()(std::uint64_t at, std::span<std::uint8_t> bytes) {
        const std::size_t c = std::size_t(at / chunk);
        if (at % chunk != 0 || c >= calls.size()) return; // counted as a missing call below
        ++calls[c];
        sizes[c] = bytes.size();
        for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = patternByte(at + i);
    }
};

/// The file holds the pattern, exactly `size` bytes of it, every chunk filled once.
void checkPatternFile(const fs::path& path, std::uint64_t size, const PatternFill& fill) {
    for (std::size_t c = 0; c < fill.calls.size(); ++c) {
        INFO("chunk " << c);
        CHECK(fill.calls[c].load() == 1);
        CHECK(fill.sizes[c] == std::min(fill.chunk, size - c * fill.chunk));
    }
    REQUIRE(fs::file_size(path) == size);
    const std::vector<std::uint8_t> bytes = fileBytes(path);
    std::size_t wrong = 0;
    for (std::uint64_t i = 0; i < size; ++i) wrong += bytes[std::size_t(i)] != patternByte(i);
    CHECK(wrong == 0);
}

bool directFlagOn(int fd) { return (::fcntl(fd, F_GETFL) & O_DIRECT) != 0; }

/// A file system whose direct writes fail with EINVAL (a block larger than the alignment).
ssize_t refuseDirect(int fd, const void* bytes, std::size_t count, off_t offset) {
    if (directFlagOn(fd)) {
        errno = EINVAL;
        return -1;
    }
    return ::pwrite(fd, bytes, count, offset);
}

/// Writes cut short: at most 1000 bytes a call, so direct ones end mid-block.
ssize_t shortWrites(int fd, const void* bytes, std::size_t count, off_t offset) {
    return ::pwrite(fd, bytes, std::min<std::size_t>(count, 1000), offset);
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
        PatternFill fill(size, chunk);
        {
            PendingFile file(path.string());
            ChunkedOutput out(file.fd(), "test output", chunk);
            out.write(size, std::ref(fill));
            file.publish();
        }
        checkPatternFile(path, size, fill);
        fs::remove(path);
    }
}

TEST_CASE("A chunked output written in ranges, on threads of its own, holds every byte where the fill put it",
          "[vdb][chunked]") {
    const std::uint64_t chunk = 2 * ChunkedOutput::kAlignment, size = 7 * chunk + 555;
    const fs::path path = scratch("ranges.bin");
    fs::remove(path);
    PatternFill fill(size, chunk);
    {
        PendingFile file(path.string());
        ChunkedOutput out(file.fd(), "test output", chunk);
        // The middle first, on 3 threads, then the start (one thread), then the end (more threads than chunks).
        out.writeRangeOnThreads(2 * chunk, 5 * chunk, std::ref(fill), 3);
        out.writeRangeOnThreads(0, 2 * chunk, std::ref(fill), 1);
        out.writeRange(5 * chunk, size, std::ref(fill));
        REQUIRE(::ftruncate(file.fd(), off_t(size)) == 0);
        file.publish();
    }
    checkPatternFile(path, size, fill);
    // A failing fill on one thread fails the range, once every thread stopped.
    {
        PendingFile file(path.string());
        ChunkedOutput out(file.fd(), "test output", chunk);
        CHECK_THROWS_WITH(out.writeRangeOnThreads(0, 9 * chunk,
                                                  [&](std::uint64_t at, std::span<std::uint8_t> bytes) {
                                                      if (at == 4 * chunk) throw Error("no such record");
                                                      std::fill(bytes.begin(), bytes.end(), std::uint8_t(1));
                                                  },
                                                  4),
                          "no such record");
    }
    fs::remove(path);
}

namespace {

/// Writes the pattern through `call`, which fails direct writes: the file
/// must start direct, end buffered, and hold every byte.
void checkFallback(const fs::path& path, std::uint64_t size, std::uint64_t chunk, ChunkedOutput::WriteCall call) {
    fs::remove(path);
    PatternFill fill(size, chunk);
    PendingFile file(path.string());
    ChunkedOutput out(file.fd(), "test output", chunk, call);
    // The scratch directory's file system takes O_DIRECT (ext4 on the
    // machines the tests run on): else this would not test the fallback.
    REQUIRE(out.direct());
    out.write(size, std::ref(fill));
    CHECK(!out.direct());
    file.publish();
    checkPatternFile(path, size, fill);
}

} // namespace

TEST_CASE("A chunked output falls back to the page cache where direct writes fail", "[vdb][chunked]") {
    const std::uint64_t chunk = ChunkedOutput::kAlignment, size = 9 * chunk + 77;
    const fs::path path = scratch("fallback.bin");
    SECTION("EINVAL from every direct write, on several threads at once") {
        // Repeated: the threads meet the failure together, and each must retry.
        for (int run = 0; run < 20; ++run) checkFallback(path, size, chunk, refuseDirect);
    }
    SECTION("direct writes cut short mid-block") { checkFallback(path, size, chunk, shortWrites); }
    fs::remove(path);
}

TEST_CASE("A chunked output reaches its name only when published, and a failing fill fails the write", "[vdb][chunked]") {
    const fs::path path = scratch("exists.bin");
    std::ofstream(path) << "kept";
    {
        PendingFile file(path.string());
        ChunkedOutput out(file.fd(), "test output", ChunkedOutput::kAlignment);
        CHECK_THROWS_WITH(out.write(10 * ChunkedOutput::kAlignment,
                                    [](std::uint64_t at, std::span<std::uint8_t> bytes) {
                                        if (at == 7 * ChunkedOutput::kAlignment) throw Error("no such record");
                                        std::fill(bytes.begin(), bytes.end(), std::uint8_t(1));
                                    }),
                          "no such record");
        CHECK(fileBytes(path).size() == 4); // untouched while the output is pending
    }
    CHECK(fileBytes(path).size() == 4);
    std::size_t temporaries = 0;
    for (const auto& e : fs::directory_iterator(path.parent_path()))
        temporaries += e.path().filename().string().starts_with("exists.bin.partial");
    CHECK(temporaries == 0); // the unpublished temporary is gone
    fs::remove(path);
}

TEST_CASE("A pending file reaches its name whole at publish, and one never published leaves nothing", "[vdb][chunked][files]") {
    const fs::path path = scratch("pending.txt");
    std::ofstream(path) << "old";
    const auto temporaries = [&] {
        std::size_t n = 0;
        for (const auto& e : fs::directory_iterator(path.parent_path()))
            n += e.path().filename().string().starts_with("pending.txt.partial-");
        return n;
    };
    {
        PendingFile file(path.string());
        CHECK(file.temporaryPath().starts_with(path.string() + ".partial-"));
        const std::string text = "new bytes";
        file.append(text.data(), text.size());
        file.writeAt(0, "N", 1);
        CHECK(fileBytes(path).size() == 3); // the old file until the rename
        CHECK(temporaries() == 1);
        file.publish();
        CHECK(temporaries() == 0);
    }
    const std::vector<std::uint8_t> published = fileBytes(path);
    CHECK(std::string(published.begin(), published.end()) == "New bytes");
    {
        PendingFile abandoned(path.string());
        abandoned.append("x", 1);
        abandoned.sync();
    }
    CHECK(fileBytes(path) == published);
    CHECK(temporaries() == 0);

    // A directory holding the name: refused before any temporary is made,
    // one error naming what is there, and nothing is left.
    const fs::path blocked = scratch("blocked");
    fs::create_directories(blocked / "inside");
    const std::uint8_t byte = 1;
    CHECK_THROWS_WITH(writeFileAtomically(blocked.string(), std::span(&byte, 1)),
                      Catch::StartsWith("cannot write " + blocked.string() + ": it is a directory"));
    std::size_t left = 0;
    for (const auto& e : fs::directory_iterator(blocked.parent_path()))
        left += e.path().filename().string().starts_with("blocked.partial-");
    CHECK(left == 0);
    fs::remove_all(blocked);
    fs::remove(path);
}

TEST_CASE("A .vdb written on one core of several asks TBB for no workers it cannot have", "[vdb][chunked][cli]") {
    // The writers' arena was the machine's size: on one allowed core TBB
    // printed "TBB Warning: The number of workers is currently limited to 0".
    if (std::thread::hardware_concurrency() < 2) return; // one core: nothing to restrict
    test::ScratchDir scratch("yv_one_core");
    const std::string bcc = (scratch.path / "g.bcc").string(), vdb = (scratch.path / "g.vdb").string();
    REQUIRE(test::runYarnvox("gen --crossings 40 --quiet -o " + bcc).exitCode == 0);
    const auto r = test::runShell("taskset -c 0 " + std::string(YV_BINARY_DIR) + "/yarnvox voxelize " + bcc + " -o " + vdb +
                                  " --backend cpu --resolution 64 --quiet");
    INFO(r.output);
    CHECK(r.exitCode == 0);
    CHECK(r.output.find("TBB") == std::string::npos);
    CHECK(r.output.empty());
}

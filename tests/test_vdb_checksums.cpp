// The checksum of each grid a yarnvox .vdb records (vdb/grid_checksums.h,
// formats/vdb-subset.md): written by the streaming writer, read by OpenVDB
// as any metadata, checked by inspect --verify and before every export; a
// flipped byte in any grid is named in one line, and an export of a cut or
// damaged file writes nothing.
#include "core/error.h"
#include "run_cli.h"
#include "test_helpers.h"
#include "vdb/grid_checksums.h"
#include "vdb/vdb_file_check.h"
#include "vdb/vdb_index.h"

#include <catch2/catch.hpp>
#include <openvdb/openvdb.h>

#include <filesystem>
#include <fstream>
#include <random>

using namespace yv;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

struct Scratch : test::ScratchDir {
    Scratch() : test::ScratchDir("yv_test_vdb_checksums") {}
};

void putByte(const std::string& path, std::uint64_t at, std::uint8_t value) {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(std::streamoff(at));
    f.put(char(value));
}

std::uint8_t byteAt(const std::string& path, std::uint64_t at) {
    std::ifstream f(path, std::ios::binary);
    f.seekg(std::streamoff(at));
    return std::uint8_t(f.get());
}

/// A voxelized garment (CPU backend, a preview level), with `extra` options.
std::string voxelized(const fs::path& dir, const std::string& name, const std::string& extra = "") {
    const fs::path bcc = dir / "g.bcc", out = dir / name;
    if (!fs::exists(bcc))
        REQUIRE(test::runYarnvox("gen --pattern knit --shape cylinder --crossings 80 --quiet -o " + bcc.string()).exitCode == 0);
    const auto r = test::runYarnvox("voxelize " + bcc.string() + " -o " + out.string() +
                                    " --backend cpu --resolution 80 --yarn-radius 0.12 --quiet" + extra);
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    return out.string();
}

std::size_t lines(const std::string& s) { return std::size_t(std::count(s.begin(), s.end(), '\n')); }

/// Neither the export's files nor a temporary of theirs in `dir`.
bool exportLeftNothing(const fs::path& dir) {
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string name = e.path().filename().string();
        if (name.starts_with("e.") || name.find(".partial-") != std::string::npos) return false;
    }
    return true;
}

} // namespace

TEST_CASE("Grid checksums: pieces added in any order give one sum, and every byte counts", "[vdb][checksums]") {
    std::vector<std::uint8_t> bytes(5 * kChecksumBlockBytes + 123);
    std::mt19937 rng(3);
    for (std::uint8_t& b : bytes) b = std::uint8_t(rng());
    const std::uint64_t begin = 1000, end = bytes.size() - 7;
    RangeChecksum whole(begin, end), backwards(begin, end);
    whole.add(0, bytes);
    for (std::uint64_t at = bytes.size() / kChecksumBlockBytes * kChecksumBlockBytes;; at -= kChecksumBlockBytes) {
        backwards.add(at, std::span(bytes).subspan(at, std::min<std::uint64_t>(kChecksumBlockBytes, bytes.size() - at)));
        if (at == 0) break;
    }
    CHECK(whole.value() == backwards.value());
    for (const std::uint64_t at : {begin, begin + 1, 4096ul, end - 1}) {
        std::vector<std::uint8_t> changed = bytes;
        changed[at] ^= 1;
        RangeChecksum other(begin, end);
        other.add(0, changed);
        CHECK(other.value() != whole.value());
    }
    // Bytes outside the range do not count.
    std::vector<std::uint8_t> outside = bytes;
    outside[begin - 1] ^= 1;
    outside[end] ^= 1;
    RangeChecksum same(begin, end);
    same.add(0, outside);
    CHECK(same.value() == whole.value());
    CHECK(checksumText({"density", "orientation"}, {0x1234, ~0ull}) == "density=0000000000001234 orientation=ffffffffffffffff");
}

TEST_CASE("Grid checksums: yarnvox's .vdb records one per grid, OpenVDB reads the file, and --verify passes", "[vdb][checksums][cli]") {
    Scratch scratch;
    for (const std::string& extra : {std::string(""), std::string(" --vdb-compression blosc --precision half --lod 2")}) {
        INFO(extra);
        const std::string vdb = voxelized(scratch.path, "v.vdb", extra);
        const VdbIndex index(vdb);
        const StoredMetadata* item = nullptr;
        for (const StoredMetadata& m : index.fileMetadata())
            if (m.name == kGridChecksumsName) item = &m;
        REQUIRE(item);
        const std::string text(item->value.begin(), item->value.end());
        CHECK(text.starts_with("density="));
        CHECK_THAT(text, Contains(" orientation="));
        CHECK(std::count(text.begin(), text.end(), '=') == index.gridCount());
        CHECK(checkVdbFile(vdb).gridsChecked == index.gridCount());
        // OpenVDB's own tools read it, the item as any string.
        const auto printed = test::runShell("vdb_print -m " + vdb);
        INFO(printed.output);
        CHECK(printed.exitCode == 0);
        CHECK_THAT(printed.output, Contains(kGridChecksumsName));
        const auto verified = test::runYarnvox("inspect " + vdb + " --verify");
        INFO(verified.output);
        CHECK(verified.exitCode == 0);
        CHECK_THAT(verified.output, Contains("verified: the bytes of all " + std::to_string(index.gridCount()) + " grids match"));
        fs::remove(vdb);
    }
}

TEST_CASE("Grid checksums: a flipped byte in any grid is named by --verify and refused by export, which writes nothing", "[vdb][checksums][cli]") {
    Scratch scratch;
    const std::string good = voxelized(scratch.path, "good.vdb");
    const VdbIndex index(good);
    std::vector<std::pair<std::string, std::uint64_t>> places; // grid, byte
    for (const VdbGridInfo& g : index.grids()) {
        places.emplace_back(g.name, g.blockPos + 66); // a value of its first leaf
        places.emplace_back(g.name, (g.blockPos + g.endPos) / 2);
    }
    places.emplace_back("orientation", index.grid("orientation")->topologyPos + 20);
    for (const auto& [grid, at] : places) {
        INFO(grid << " byte " << at);
        const std::string bad = (scratch.path / "bad.vdb").string();
        fs::copy_file(good, bad, fs::copy_options::overwrite_existing);
        putByte(bad, at, std::uint8_t(byteAt(bad, at) ^ 0x10));
        const auto verify = test::runYarnvox("inspect " + bad + " --verify");
        INFO(verify.output);
        CHECK(verify.exitCode == 1);
        CHECK_THAT(verify.output, Contains("yarnvox: error: " + bad + ": "));
        CHECK_THAT(verify.output, Contains("grid '" + grid + "'"));
        CHECK(lines(verify.output) == 1);
        for (const char* out : {"e.vol", "e.nvdb"}) {
            const auto exported = test::runYarnvox("export " + bad + " -o " + (scratch.path / out).string());
            INFO(exported.output);
            CHECK(exported.exitCode == 1);
            CHECK_THAT(exported.output, Contains("yarnvox: error: " + bad + ": ") && Contains("grid '" + grid + "'"));
            CHECK(lines(exported.output) == 1);
            CHECK(exportLeftNothing(scratch.path));
        }
    }
}

TEST_CASE("Grid checksums: export refuses a cut .vdb, or one whose names and counts are damaged, in one short line", "[vdb][checksums][cli]") {
    Scratch scratch;
    const std::string good = voxelized(scratch.path, "good.vdb");
    const auto size = fs::file_size(good);
    const VdbIndex index(good);
    const std::string bad = (scratch.path / "bad.vdb").string();
    const auto damaged = [&](const std::function<void()>& damage) {
        fs::copy_file(good, bad, fs::copy_options::overwrite_existing);
        damage();
        const auto r = test::runYarnvox("export " + bad + " -o " + (scratch.path / "e.vol").string());
        INFO(r.output);
        CHECK(r.exitCode == 1);
        CHECK_THAT(r.output, Contains("yarnvox: error: " + bad));
        CHECK(lines(r.output) == 1);
        CHECK(r.output.size() < 400);
        CHECK(exportLeftNothing(scratch.path));
    };
    for (const std::uintmax_t keep : {size - 1, size / 2, std::uintmax_t(300)})
        damaged([&] { fs::resize_file(bad, keep); });
    // The first grid's name claims 60000 bytes: the message still names it in a few words.
    damaged([&] {
        putByte(bad, index.gridsPos(), 0x60);
        putByte(bad, index.gridsPos() + 1, 0xea);
    });
    // The recorded checksums themselves changed (the header is not covered: the sums are then wrong).
    damaged([&] {
        std::ifstream in(good, std::ios::binary);
        const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
        const std::size_t at = bytes.find("density=");
        REQUIRE(at != std::string::npos);
        putByte(bad, at + 8, bytes[at + 8] == '0' ? '1' : '0');
    });
}

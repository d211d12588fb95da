#include "core/error.h"
#include "core/packed_bricks.h"
#include "cpu/cpu_voxelizer.h"
#include "garment/cross_section.h"
#include "store/brick_store.h"
#include "store/region_writer.h"
#include "packed_test_bricks.h"
#include "test_helpers.h"
#include "vdb/merge.h"
#include "vdb/vdb_writer.h"
#include "vdb_bytes.h"

#include <catch2/catch.hpp>
#include <openvdb/openvdb.h>
#include <tbb/global_control.h>

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <random>

using namespace yv;
namespace fs = std::filesystem;

namespace {

// A fresh directory per test; the store itself is made in a subfolder so
// tests can also point it at a path that does not exist yet.
struct ScratchDir {
    fs::path path;
    ScratchDir() {
        std::random_device rd;
        path = fs::temp_directory_path() / ("yv_test_store_" + std::to_string(::getpid()) + "_" + std::to_string(rd()));
        fs::create_directories(path);
    }
    ~ScratchDir() { fs::remove_all(path); }
    std::string sub(const std::string& name) const { return (path / name).string(); }
};

VoxelGrid testGrid() {
    VoxelGrid g;
    g.origin = {-1.5, 0.25, 3.0};
    g.voxelSize = 0.0125;
    g.dims = {256, 256, 256};
    return g;
}

StoreManifest testManifest(std::uint64_t fingerprint = 0x1234abcd5678ef01ULL, Reduce reduce = Reduce::Mean) {
    StoreManifest m;
    m.fingerprint = fingerprint;
    m.grid = testGrid();
    m.reduce = reduce;
    return m;
}

/// Region `id` read chunk by chunk (forEachChunk), back as bricks sorted by key.
std::vector<VoxelBrick> readByChunks(const BrickStore& store, std::uint64_t id) {
    std::vector<VoxelBrick> out;
    std::mutex lock;
    store.forEachChunk(id, [&](const RawBricks& chunk) {
        for (std::size_t i = 0; i < chunk.count; ++i) {
            VoxelBrick b;
            b.key = chunk.keys[i];
            std::copy_n(chunk.activeMask(i), b.activeMask.size(), b.activeMask.begin());
            std::copy_n(chunk.density(i), kBrickVoxels, b.density.begin());
            std::copy_n(chunk.orientation(i), kBrickVoxels, b.orientation.begin());
            const std::lock_guard guard(lock);
            out.push_back(b);
        }
    });
    std::sort(out.begin(), out.end(), [](const VoxelBrick& a, const VoxelBrick& b) { return a.key < b.key; });
    return out;
}

const glm::ivec3 kAll0{0}, kAll1{256};

/// Every bit random, NaNs included: the round trip must be bit-exact, not just equal.
VoxelBrick randomBrick(std::mt19937_64& rng, std::uint64_t key) {
    VoxelBrick b;
    b.key = key;
    for (auto& w : b.activeMask) w = rng();
    for (float& d : b.density) d = std::bit_cast<float>(static_cast<std::uint32_t>(rng()));
    for (glm::vec3& o : b.orientation)
        for (int i = 0; i < 3; ++i) o[i] = std::bit_cast<float>(static_cast<std::uint32_t>(rng()));
    return b;
}

/// What the voxelizer makes: few active voxels, zeros elsewhere.
VoxelBrick sparseBrick(std::mt19937_64& rng, std::uint64_t key) {
    VoxelBrick b;
    b.key = key;
    for (int n = 0; n < 5; ++n) {
        const int v = int(rng() % kBrickVoxels);
        b.activeMask[v >> 6] |= std::uint64_t(1) << (v & 63);
        b.density[v] = float(rng() % 1000 + 1) / 1000.0f;
        b.orientation[v] = glm::normalize(glm::vec3(float(rng() % 7) - 3, float(rng() % 5) - 2, 1.0f));
    }
    return b;
}

bool sameBits(const VoxelBrick& a, const VoxelBrick& b) {
    return a.key == b.key && std::memcmp(a.activeMask.data(), b.activeMask.data(), sizeof a.activeMask) == 0 &&
           std::memcmp(a.density.data(), b.density.data(), sizeof a.density) == 0 &&
           std::memcmp(a.orientation.data(), b.orientation.data(), sizeof a.orientation) == 0;
}

/// Distinct brick keys inside the test grid, in random order.
std::vector<std::uint64_t> randomKeys(std::mt19937_64& rng, std::size_t n) {
    std::vector<std::uint64_t> all;
    for (int x = 0; x < 32; ++x)
        for (int y = 0; y < 32; ++y)
            for (int z = 0; z < 32; ++z) all.push_back(brickKey({x, y, z}));
    std::shuffle(all.begin(), all.end(), rng);
    all.resize(n);
    return all;
}

std::vector<std::uint8_t> fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void putFile(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

std::vector<std::string> entriesOf(const std::string& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

} // namespace

TEST_CASE("xxh64 gives the reference XXH64 values", "[store]") {
    const std::string spam = "Nobody inspects the spammish repetition";
    CHECK(xxh64("", 0) == 0xEF46DB3751D8E999ULL);
    CHECK(xxh64("a", 1) == 0xD24EC4F1A98C6E5BULL);
    CHECK(xxh64("abc", 3) == 0x44BC2CF5AD770999ULL);
    CHECK(xxh64(spam.data(), spam.size()) == 0xFBCEA83C8A378BF1ULL);
    // Values the hand-written XXH64 of yarnvox 8d8d9c1 gave, before libxxhash took its place.
    CHECK(xxh64("yarnvox", 7) == 0x149D6B6AFDA538BFULL);
    const std::string x31(31, 'x'), x32(32, 'x'), y33(33, 'y');
    CHECK(xxh64(x31.data(), x31.size()) == 0x60DD0D01083B99F0ULL);
    CHECK(xxh64(x32.data(), x32.size()) == 0xE2DF261FC2EC30EBULL);
    CHECK(xxh64(y33.data(), y33.size()) == 0xF27D5A84556CAEF4ULL);
    std::vector<std::uint8_t> megabyte(1 << 20);
    for (std::size_t i = 0; i < megabyte.size(); ++i) megabyte[i] = std::uint8_t((i * 131u + 7u) >> 3);
    CHECK(xxh64(megabyte.data(), megabyte.size()) == 0x1B5767319807C2E1ULL);
}

namespace {

const std::string kOldWorkDir = std::string(YV_SOURCE_DIR) + "/tests/data/work-dir-8d8d9c1";

} // namespace

TEST_CASE("A region file of yarnvox 8d8d9c1 reads as valid and encodes again to the same bytes", "[store]") {
    const std::string path = kOldWorkDir + "/region-0.yvb";
    const std::vector<std::uint8_t> bytes = fileBytes(path);
    REQUIRE(bytes.size() == 13113);
    const RegionHeader h = parseRegionHeader(bytes.data(), bytes.size(), path);
    std::vector<VoxelBrick> bricks;
    decodeRegionBody(bytes.data(), h, path, &bricks); // every checksum of the file, through libxxhash
    CHECK(bricks.size() == 18);
    CHECK(h.activeVoxels == 601);

    // The same bricks written by today's store, for the same run: the same bytes.
    StoreManifest run;
    run.fingerprint = h.fingerprint;
    run.grid = h.grid;
    run.reduce = h.reduce;
    ScratchDir scratch;
    const std::string dir = scratch.sub("w");
    BrickStore store(dir, run, false);
    store.writeRegion(h.id, h.min, h.max, bricks);
    CHECK(fileBytes(store.regionPath(h.id)) == bytes);
}

TEST_CASE("A work dir of yarnvox 8d8d9c1 (text manifest) is refused with one line, and nothing is deleted", "[store]") {
    ScratchDir scratch;
    const std::string dir = scratch.sub("w");
    fs::create_directories(dir);
    for (const char* name : {"manifest", "region-0.yvb"}) fs::copy_file(kOldWorkDir + "/" + name, dir + "/" + name);
    const std::string line = dir + "/manifest: work dir written by an older yarnvox (manifest format)";
    CHECK_THAT(errorOf([&] { readManifest(dir); }), Catch::StartsWith(line) && Catch::Contains("without --resume"));
    CHECK_THAT(errorOf([&] { BrickStore store(dir); }), Catch::StartsWith(line));              // inspect
    CHECK_THAT(errorOf([&] { BrickStore(dir, testManifest(), true); }), Catch::StartsWith(line)); // --resume
    CHECK_THAT(errorOf([&] { mergeStoreToVdb(dir, scratch.sub("m.vdb"), VolumeMetadata{}); }), Catch::StartsWith(line));
    CHECK_THAT(errorOf([&] { loadStore(dir); }), Catch::StartsWith(line));
    CHECK(errorOf([&] { readManifest(dir); }).find('\n') == std::string::npos);
    CHECK(entriesOf(dir) == std::vector<std::string>{"manifest", "region-0.yvb"});
    CHECK_FALSE(fs::exists(scratch.sub("m.vdb")));
    // Without --resume the run starts the work dir over.
    { BrickStore store(dir, testManifest(), false); }
    CHECK(entriesOf(dir) == std::vector<std::string>{"manifest"});
    CHECK(readManifest(dir).fingerprint == testManifest().fingerprint);
}

TEST_CASE("Regions round-trip bit-exactly, sorted by key, across several chunks", "[store]") {
    ScratchDir scratch;
    const std::string dir = scratch.sub("work"); // created by the store
    BrickStore store(dir, testManifest(), false);
    std::mt19937_64 rng(7);

    // 2100 bricks span two 2048-brick chunks; a few are fully random.
    const std::vector<std::uint64_t> keys = randomKeys(rng, 2100);
    std::vector<VoxelBrick> bricks;
    for (std::size_t i = 0; i < keys.size(); ++i)
        bricks.push_back(i % 500 == 3 ? randomBrick(rng, keys[i]) : sparseBrick(rng, keys[i]));
    std::map<std::uint64_t, VoxelBrick> expected;
    std::uint64_t active = 0;
    for (const VoxelBrick& b : bricks) {
        expected[b.key] = b;
        active += b.activeCount();
    }

    RegionWriteTimings timings;
    const RegionInfo info = store.writeRegion(42, kAll0, kAll1, bricks, &timings);
    CHECK(info.id == 42);
    CHECK(info.brickCount == 2100);
    CHECK(info.activeVoxels == active);
    CHECK(info.bytesOnDisk == fs::file_size(store.regionPath(42)));
    CHECK(info.bytesOnDisk < 2100 * 8256 / 4); // sparse bricks compress
    CHECK(timings.encodeSeconds > 0);

    const std::vector<VoxelBrick> back = store.readRegion(42);
    REQUIRE(back.size() == expected.size());
    std::size_t i = 0, mismatches = 0;
    for (const auto& [key, brick] : expected) mismatches += !sameBits(back[i++], brick);
    CHECK(mismatches == 0);
    // Chunk by chunk, on several threads, the same bricks.
    const std::vector<VoxelBrick> chunked = readByChunks(store, 42);
    REQUIRE(chunked.size() == expected.size());
    i = 0;
    for (const auto& [key, brick] : expected) mismatches += !sameBits(chunked[i++], brick);
    CHECK(mismatches == 0);

    // An empty region is a file too: a resumed run must know it is done.
    const RegionInfo empty = store.writeRegion(7, {8, 8, 8}, {16, 16, 16}, {});
    CHECK(empty.brickCount == 0);
    CHECK(store.readRegion(7).empty());
    CHECK(store.hasVerifiedRegion(7, {8, 8, 8}, {16, 16, 16}));
    CHECK(store.hasVerifiedRegion(42, kAll0, kAll1));

    const std::vector<RegionInfo> listed = store.listRegions();
    REQUIRE(listed.size() == 2);
    CHECK(listed[0].id == 7);
    CHECK(listed[1].id == 42);
    CHECK(listed[1].activeVoxels == active);
    CHECK(listed[1].max == kAll1);
    CHECK(store.bytesOnDisk() == info.bytesOnDisk + empty.bytesOnDisk);
    // Atomic writes leave nothing but finished files behind.
    CHECK(entriesOf(dir) == std::vector<std::string>{"manifest", "region-42.yvb", "region-7.yvb"});
}

TEST_CASE("writeRegion refuses duplicate bricks and bricks outside the region, leaving nothing", "[store]") {
    ScratchDir scratch;
    BrickStore store(scratch.sub("w"), testManifest(), false);
    std::mt19937_64 rng(1);
    const VoxelBrick a = sparseBrick(rng, brickKey({1, 2, 3}));
    CHECK_THAT(errorOf([&] { store.writeRegion(1, kAll0, kAll1, {a, sparseBrick(rng, a.key)}); }),
               Catch::Contains("given twice"));
    CHECK_THAT(errorOf([&] { store.writeRegion(1, {16, 0, 0}, {64, 64, 64}, {a}); }),
               Catch::Contains("outside the region"));
    CHECK(entriesOf(store.dir()) == std::vector<std::string>{"manifest"});
}

TEST_CASE("Damaged region files are detected, reported and removed", "[store]") {
    ScratchDir scratch;
    BrickStore store(scratch.sub("w"), testManifest(), false);
    std::mt19937_64 rng(3);
    std::vector<VoxelBrick> bricks;
    for (std::uint64_t key : randomKeys(rng, 3)) bricks.push_back(sparseBrick(rng, key));
    store.writeRegion(5, kAll0, kAll1, bricks);
    const std::string path = store.regionPath(5);
    const std::vector<std::uint8_t> good = fileBytes(path);
    REQUIRE(good.size() > 200);

    struct Damage {
        const char* what;
        std::function<void(std::vector<std::uint8_t>&)> apply;
        const char* message;
    };
    const std::vector<Damage> damages = {
        {"header byte", [](auto& b) { b[40] ^= 0x10; }, "byte 152: header checksum mismatch"},
        {"magic", [](auto& b) { b[0] = 'X'; }, "byte 0: expected magic"},
        {"key index", [](auto& b) { b[165] ^= 0x01; }, "byte 160: checksum mismatch over the brick index"},
        {"payload", [](auto& b) { b.back() ^= 0x80; }, "checksum mismatch: the compressed data is damaged"},
        {"truncation", [](auto& b) { b.resize(b.size() / 2); }, "truncated"},
        {"appended byte", [](auto& b) { b.push_back(0); }, "trailing bytes"},
    };
    for (const Damage& d : damages) {
        SECTION(d.what) {
            std::vector<std::uint8_t> bad = good;
            d.apply(bad);
            putFile(path, bad);
            const std::string message = errorOf([&] { store.readRegion(5); });
            CHECK_THAT(message, Catch::StartsWith(path + ": ") && Catch::Contains(d.message));
            CHECK(errorOf([&] { readByChunks(store, 5); }) == message);
            std::string why;
            CHECK_FALSE(store.hasVerifiedRegion(5, kAll0, kAll1, &why));
            CHECK(why == message);
            CHECK_FALSE(fs::exists(path));
            CHECK_THAT(errorOf([&] { store.readRegion(5); }), Catch::Contains("region file missing"));
        }
    }
}

TEST_CASE("Every single-byte change and every truncated prefix of a region file is rejected", "[store]") {
    ScratchDir scratch;
    BrickStore store(scratch.sub("w"), testManifest(), false);
    std::mt19937_64 rng(11);
    store.writeRegion(0, kAll0, kAll1, {sparseBrick(rng, brickKey({4, 5, 6})), sparseBrick(rng, brickKey({0, 0, 1}))});
    const std::string path = store.regionPath(0);
    const std::vector<std::uint8_t> good = fileBytes(path);
    REQUIRE(store.readRegion(0).size() == 2);

    std::size_t accepted = 0;
    for (std::size_t i = 0; i < good.size(); ++i) {
        std::vector<std::uint8_t> bad = good;
        bad[i] ^= 0xA5;
        putFile(path, bad);
        accepted += errorOf([&] { store.readRegion(0); }).empty();
        accepted += errorOf([&] { readByChunks(store, 0); }).empty();
    }
    CHECK(accepted == 0);
    for (std::size_t n = 0; n < good.size(); ++n) {
        putFile(path, std::vector<std::uint8_t>(good.begin(), good.begin() + std::ptrdiff_t(n)));
        accepted += errorOf([&] { store.readRegion(0); }).empty();
        accepted += errorOf([&] { readByChunks(store, 0); }).empty();
    }
    CHECK(accepted == 0);
    putFile(path, good);
    CHECK(store.readRegion(0).size() == 2);
    CHECK(readByChunks(store, 0).size() == 2);
}

TEST_CASE("hasVerifiedRegion rejects a region of other bounds or of another run", "[store]") {
    ScratchDir scratch;
    std::mt19937_64 rng(5);
    const VoxelBrick b = sparseBrick(rng, brickKey({1, 1, 1}));
    {
        BrickStore other(scratch.sub("other"), testManifest(99), false);
        other.writeRegion(3, kAll0, kAll1, {b});
    }
    BrickStore store(scratch.sub("w"), testManifest(), false);
    store.writeRegion(3, kAll0, kAll1, {b});
    std::string why;
    CHECK_FALSE(store.hasVerifiedRegion(3, kAll0, {128, 256, 256}, &why));
    CHECK_THAT(why, Catch::Contains("differ from the plan's"));
    CHECK_FALSE(fs::exists(store.regionPath(3)));

    fs::copy_file(scratch.sub("other/region-3.yvb"), store.regionPath(3));
    CHECK_THAT(errorOf([&] { store.readRegion(3); }), Catch::Contains("belongs to another run"));
    CHECK_THAT(errorOf([&] { store.listRegions(); }), Catch::Contains("belongs to another run"));
    CHECK_FALSE(store.hasVerifiedRegion(3, kAll0, kAll1, &why));
    CHECK_THAT(why, Catch::Contains("belongs to another run"));
    CHECK_FALSE(store.hasVerifiedRegion(4, kAll0, kAll1, &why));
    CHECK_THAT(why, Catch::Contains("not on disk"));
}

TEST_CASE("Resuming keeps the regions of the same run and refuses another run", "[store]") {
    ScratchDir scratch;
    const std::string dir = scratch.sub("w");
    std::mt19937_64 rng(9);
    {
        BrickStore store(dir, testManifest(), false);
        store.writeRegion(0, kAll0, kAll1, {sparseBrick(rng, brickKey({2, 2, 2}))});
    }
    // What a crash mid-write leaves behind.
    putFile(dir + "/region-1.yvb.tmp-123-4", {1, 2, 3});
    {
        BrickStore store(dir, testManifest(), true);
        CHECK(store.hasVerifiedRegion(0, kAll0, kAll1));
        CHECK_FALSE(fs::exists(dir + "/region-1.yvb.tmp-123-4"));
        store.markComplete(1);
        CHECK_THAT(errorOf([&] { store.markComplete(2); }), Catch::Contains("1 region files on disk"));
    }
    CHECK(readManifest(dir).completeRegions == std::optional<std::uint64_t>(1));
    {
        BrickStore store(dir, testManifest(), true);
        CHECK(store.manifest().completeRegions == std::optional<std::uint64_t>(1));
    }

    const std::string wrongRun = errorOf([&] { BrickStore(dir, testManifest(0x777), true); });
    CHECK_THAT(wrongRun, Catch::StartsWith(dir + ": this work dir belongs to a different run") &&
                             Catch::Contains("fingerprint") && Catch::Contains("--work-dir") &&
                             Catch::Contains("drop --resume"));
    StoreManifest otherGrid = testManifest();
    otherGrid.grid.voxelSize *= 2;
    CHECK_THAT(errorOf([&] { BrickStore(dir, otherGrid, true); }),
               Catch::Contains("different run") && Catch::Contains("voxel size"));
    CHECK_THAT(errorOf([&] { BrickStore(dir, testManifest(0x1234abcd5678ef01ULL, Reduce::Max), true); }),
               Catch::Contains("reduce mean on disk, max for this run"));
    CHECK(fs::exists(dir + "/region-0.yvb")); // refusing changes nothing

    // Starting over clears the old run's files.
    {
        BrickStore store(dir, testManifest(0x777), false);
        CHECK(store.listRegions().empty());
        CHECK_FALSE(store.manifest().completeRegions);
    }
    CHECK(readManifest(dir).fingerprint == 0x777);
    CHECK(entriesOf(dir) == std::vector<std::string>{"manifest"});
}

TEST_CASE("A run refused for another fingerprint names a change of backend where the metadata shows one", "[store]") {
    StoreManifest disk = testManifest(), now = testManifest(0x778);
    disk.run.input = now.run.input = "g.bcc";
    disk.run.resolution = now.run.resolution = 64;
    disk.run.backend = "gl";
    now.run.backend = "cpu";
    CHECK_THAT(runDifference(disk, now), Catch::Contains("made with --backend gl, this run uses --backend cpu") &&
                                             Catch::Contains("fingerprint"));
    now.run = disk.run; // same backend: the fingerprint alone
    CHECK_THAT(runDifference(disk, now), !Catch::Contains("--backend") && Catch::Contains("fingerprint"));
    now.fingerprint = disk.fingerprint;
    CHECK(runDifference(disk, now).empty());
}

TEST_CASE("Resuming refuses regions of another yarnvox version or sampling code, naming which, and deletes nothing", "[store]") {
    ScratchDir scratch;
    const std::string dir = scratch.sub("w");
    std::mt19937_64 rng(10);
    StoreManifest old = testManifest();
    old.yarnvoxVersion = "0.0.9";
    old.samplingCode = 0xabc;
    {
        BrickStore store(dir, old, false);
        store.writeRegion(0, kAll0, kAll1, {sparseBrick(rng, brickKey({2, 2, 2}))});
    }
    const std::string manifestBefore = formatManifest(readManifest(dir));
    CHECK_THAT(manifestBefore, Catch::Contains("\"yarnvox_version\": \"0.0.9\",\n  \"sampling_code\": \"0x0000000000000abc\""));

    // The same fingerprint: only the version tells the runs apart, and the message says so.
    StoreManifest now = testManifest();
    now.samplingCode = 0xabc;
    const std::string version = errorOf([&] { BrickStore(dir, now, true); });
    CHECK_THAT(version, Catch::StartsWith(dir + ": this work dir belongs to a different run") &&
                            Catch::Contains(std::string("made by yarnvox 0.0.9, this is ") + YV_VERSION) &&
                            Catch::Contains("drop --resume"));
    CHECK_THAT(version, !Catch::Contains("fingerprint"));

    old.samplingCode = 0xdef;
    old.fingerprint = 0x999;
    {
        BrickStore store(dir, old, false);
        store.writeRegion(0, kAll0, kAll1, {sparseBrick(rng, brickKey({2, 2, 2}))});
    }
    now.yarnvoxVersion = "0.0.9";
    const std::string code = errorOf([&] { BrickStore(dir, now, true); });
    CHECK_THAT(code, Catch::Contains("the sampling code differs (0x0000000000000def on disk, 0x0000000000000abc "
                                     "in this yarnvox)"));
    CHECK_THAT(code, !Catch::Contains("made by") && !Catch::Contains("fingerprint"));

    // Refusing changed nothing.
    CHECK(entriesOf(dir) == std::vector<std::string>{"manifest", "region-0.yvb"});
    CHECK(readManifest(dir).samplingCode == 0xdef);
    now.samplingCode = 0xdef;
    now.fingerprint = 0x999;
    BrickStore same(dir, now, true);
    CHECK(same.hasVerifiedRegion(0, kAll0, kAll1));
}

TEST_CASE("A manifest of another work dir version is refused on resume, nothing deleted", "[store]") {
    ScratchDir scratch;
    const std::string dir = scratch.sub("w");
    std::mt19937_64 rng(11);
    {
        BrickStore store(dir, testManifest(), false);
        store.writeRegion(0, kAll0, kAll1, {sparseBrick(rng, brickKey({2, 2, 2}))});
    }
    std::string text = formatManifest(testManifest());
    text.replace(text.find("\"version\": 3"), 12, "\"version\": 4");
    putFile(dir + "/manifest", std::vector<std::uint8_t>(text.begin(), text.end()));
    CHECK_THAT(errorOf([&] { BrickStore(dir, testManifest(), true); }),
               Catch::Contains("\"version\": unsupported work dir version 4: expected 3 (written by another yarnvox version?)"));
    CHECK(entriesOf(dir) == std::vector<std::string>{"manifest", "region-0.yvb"});
}

TEST_CASE("A directory holding files the store did not write is never cleared", "[store]") {
    ScratchDir scratch;
    const std::string dir = scratch.sub("w");
    {
        BrickStore store(dir, testManifest(), false);
        std::mt19937_64 rng(2);
        store.writeRegion(0, kAll0, kAll1, {sparseBrick(rng, 5)});
    }
    putFile(dir + "/holiday.jpg", {0xff, 0xd8});
    const std::string message = errorOf([&] { BrickStore(dir, testManifest(), false); });
    CHECK_THAT(message, Catch::Contains("did not write") && Catch::Contains("holiday.jpg"));
    CHECK(fs::exists(dir + "/holiday.jpg"));
    CHECK(fs::exists(dir + "/region-0.yvb"));
    CHECK(fs::exists(dir + "/manifest"));

    // Resuming the same run is fine: nothing of the user's is touched.
    { BrickStore store(dir, testManifest(), true); }
    // Without a manifest there is nothing to resume: that is a fresh start, refused too.
    fs::remove(dir + "/manifest");
    CHECK_THAT(errorOf([&] { BrickStore(dir, testManifest(), true); }), Catch::Contains("did not write"));
    CHECK(fs::exists(dir + "/holiday.jpg"));
}

TEST_CASE("A work dir is used by one writer at a time, and read-only stores do not write", "[store]") {
    ScratchDir scratch;
    const std::string dir = scratch.sub("w");
    {
        BrickStore store(dir, testManifest(), false);
        CHECK_THAT(errorOf([&] { BrickStore(dir, testManifest(), true); }), Catch::Contains("another yarnvox process"));
        CHECK_THAT(errorOf([&] { BrickStore{dir}; }), Catch::Contains("another yarnvox process"));
    }
    BrickStore reader(dir);
    BrickStore reader2(dir);
    CHECK(reader.manifest().fingerprint == testManifest().fingerprint);
    CHECK(reader.manifest().grid.origin == testGrid().origin);
    CHECK(reader.manifest().grid.voxelSize == testGrid().voxelSize);
    CHECK_THAT(errorOf([&] { reader.writeRegion(0, kAll0, kAll1, {}); }), Catch::Contains("read-only"));
    CHECK_THAT(errorOf([&] { BrickStore(scratch.sub("missing")); }), Catch::Contains("cannot open work dir"));
}

TEST_CASE("The manifest keeps the run's description exactly", "[store]") {
    ScratchDir scratch;
    const std::string dir = scratch.sub("w");
    StoreManifest m = testManifest();
    // Text that looks like manifest fields or JSON must not be read as them.
    m.run.input = "a b.bcc\ncomplete 5\n\nreduce max\n\"}, {\"reduce\": \"max\"";
    m.run.backend = "cpu";
    m.run.resolution = 2048;
    m.run.sliceCount = 0x7fffffffffffffffULL;
    m.run.yarnRadius = 0.1 + 0.2; // every bit of a double
    m.run.twist = -1e-300;
    m.run.supersample = 3;
    m.run.albedo = true;
    { BrickStore store(dir, m, false); }
    StoreManifest back = readManifest(dir);
    CHECK(metadataFields(back.run) == metadataFields(m.run));
    CHECK(std::bit_cast<std::uint64_t>(back.run.yarnRadius) == std::bit_cast<std::uint64_t>(0.1 + 0.2));
    CHECK_FALSE(back.completeRegions);
    CHECK(back.reduce == Reduce::Mean);

    // Resuming adopts the latest run's description and keeps the completion mark.
    {
        BrickStore store(dir, m, true);
        store.markComplete(0, {{"read", 0.25}, {"voxelize.store_write", 1.0 / 3.0}});
    }
    m.run = VolumeMetadata{};
    m.run.input = "moved.bcc";
    { BrickStore store(dir, m, true); }
    back = readManifest(dir);
    CHECK(back.run.input == "moved.bcc");
    CHECK(back.run.resolution == 0);
    CHECK(back.completeRegions == std::optional<std::uint64_t>(0));
    CHECK(back.stageSeconds == StageSeconds{{"read", 0.25}, {"voxelize.store_write", 1.0 / 3.0}});
}

TEST_CASE("A damaged manifest is reported by field", "[store]") {
    ScratchDir scratch;
    const std::string dir = scratch.sub("w");
    { BrickStore store(dir, testManifest(), false); }
    const std::vector<std::uint8_t> bytes = fileBytes(dir + "/manifest");
    const std::string good(bytes.begin(), bytes.end());
    const auto refusal = [&](const std::string& from, const std::string& to) {
        std::string text = good;
        REQUIRE(text.find(from) != std::string::npos);
        text.replace(text.find(from), from.size(), to);
        putFile(dir + "/manifest", std::vector<std::uint8_t>(text.begin(), text.end()));
        return errorOf([&] { readManifest(dir); });
    };
    const std::string path = dir + "/manifest";
    CHECK_THAT(refusal("\"voxel_size\"", "\"voxel_sise\""), Catch::StartsWith(path + ": grid: \"voxel_sise\": no such field"));
    CHECK_THAT(refusal("\"reduce\": \"mean\"", "\"reduce\": \"mode\""), Catch::Contains("unknown reduce mode \"mode\""));
    CHECK_THAT(refusal("\"backend\": \"\"", "\"backend\": 1"), Catch::Contains(": run: \"backend\": expected a string"));
    CHECK_THAT(refusal("\"supersample\": 1", "\"supersample\": 1.5"), Catch::Contains("\"supersample\": expected an integer"));
    CHECK_THAT(refusal("\"fingerprint\": \"0x", "\"fingerprint\": \"1x"), Catch::Contains("\"fingerprint\": expected \"0x\""));
    CHECK_THAT(refusal("\"dims\": [", "\"dims\": [7, "), Catch::Contains("\"dims\": expected an array of 3"));
    CHECK_THAT(refusal("\"run\": {", "\"extra\": 1, \"run\": {"), Catch::Contains("\"extra\": no such field"));
    CHECK_THAT(refusal("}\n", "}\nextra\n"), Catch::StartsWith(path + ": not JSON"));
    putFile(dir + "/manifest", {});
    CHECK_THAT(errorOf([&] { readManifest(dir); }), Catch::StartsWith(path + ": not JSON"));
    CHECK_THAT(errorOf([&] { BrickStore(dir, testManifest(), true); }), Catch::Contains("not JSON"));
    putFile(dir + "/manifest", {'[', ']'});
    CHECK_THAT(errorOf([&] { readManifest(dir); }), Catch::Contains("expected a JSON object"));
    CHECK_THAT(errorOf([&] { readManifest(scratch.sub("nothing")); }), Catch::Contains("no manifest"));
}

namespace {

/// One region per x-column of bricks; brick y, z and the voxels are random.
/// Every seventh accumulator stays empty and must be dropped.
struct AccumulatorRegion {
    std::uint64_t id;
    glm::ivec3 min, max;
    std::vector<BrickAccumulator> accumulators;
};

std::vector<AccumulatorRegion> makeAccumulatorRegions(int count, int perRegion) {
    std::mt19937_64 rng(21);
    std::vector<AccumulatorRegion> regions;
    for (int r = 0; r < count; ++r) {
        AccumulatorRegion region{std::uint64_t(r), {8 * r, 0, 0}, {8 * r + 8, 256, 256}, {}};
        std::vector<std::uint64_t> keys;
        while (int(keys.size()) < perRegion) {
            const std::uint64_t key = brickKey({r, int(rng() % 32), int(rng() % 32)});
            if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
        }
        for (std::size_t k = 0; k < keys.size(); ++k) {
            BrickAccumulator acc;
            acc.key = keys[k];
            acc.words.assign(kMeanWords * kBrickVoxels, 0);
            if ((r * perRegion + k) % 7 != 3)
                for (int s = 0; s < 20; ++s) {
                    const glm::dvec3 dir(double(rng() % 9) - 4, double(rng() % 9) - 4, 1.0);
                    accumulateSample(Reduce::Mean, acc.words.data(), int(rng() % kBrickVoxels),
                                     double(rng() % 100 + 1) / 400.0, 1.0f, glm::normalize(dir));
                }
            region.accumulators.push_back(std::move(acc));
        }
        regions.push_back(std::move(region));
    }
    return regions;
}

} // namespace

TEST_CASE("RegionWriter with a tiny queue bound writes every region, as resolveVolume resolves them", "[store]") {
    const std::size_t bound = GENERATE(std::size_t(1), std::size_t(64) << 20);
    ScratchDir scratch;
    const std::string dir = scratch.sub("w");
    const std::vector<AccumulatorRegion> regions = makeAccumulatorRegions(32, 6);
    std::vector<BrickAccumulator> all;
    for (const auto& r : regions) all.insert(all.end(), r.accumulators.begin(), r.accumulators.end());
    const BrickVolume expected = resolveVolume(testGrid(), Reduce::Mean, Overlap::Clamp, all);
    REQUIRE(expected.bricks.size() < all.size()); // some accumulators resolve to nothing

    {
        BrickStore store(dir, testManifest(), false);
        RegionWriter writer(store, Reduce::Mean, Overlap::Clamp, bound, 3);
        for (const auto& r : regions) writer.submit(r.id, r.min, r.max, r.accumulators);
        const std::vector<RegionInfo> infos = writer.finish();
        REQUIRE(infos.size() == regions.size());
        for (std::size_t i = 0; i < infos.size(); ++i) CHECK(infos[i].id == i);
        const RegionWriterStats stats = writer.stats();
        CHECK(stats.regionsWritten == regions.size());
        CHECK(stats.bricksWritten == expected.bricks.size());
        CHECK(stats.bytesWritten == store.bytesOnDisk());
        const std::size_t oneRegion = 6 * kMeanWords * kBrickVoxels * sizeof(std::uint32_t);
        CHECK(stats.peakQueuedBytes >= oneRegion);
        if (bound == 1) CHECK(stats.peakQueuedBytes < 2 * oneRegion); // one region held at a time
        CHECK(store.listRegions().size() == regions.size());
        store.markComplete(regions.size());
    }
    const BrickVolume back = loadStore(dir);
    REQUIRE(back.bricks.size() == expected.bricks.size());
    std::size_t mismatches = 0;
    for (std::size_t i = 0; i < back.bricks.size(); ++i) mismatches += !sameBits(back.bricks[i], expected.bricks[i]);
    CHECK(mismatches == 0);
    CHECK(back.activeVoxelCount() == expected.activeVoxelCount());
}

namespace {

/// What the GPU resolve reads back for a region, built here with resolveBrick.
PackedBricks packOnCpu(const std::vector<BrickAccumulator>& accumulators) {
    std::vector<VoxelBrick> bricks;
    std::vector<ResolveTally> tallies;
    for (const BrickAccumulator& a : accumulators) {
        VoxelBrick b;
        ResolveTally t;
        if (!resolveBrick(Reduce::Mean, Overlap::Clamp, a, b, &t)) continue;
        bricks.push_back(std::move(b));
        tallies.push_back(t);
    }
    PackedBricks packed = test::packBricks(bricks);
    for (std::size_t i = 0; i < tallies.size(); ++i) {
        PackedBrickHeader& h = packed.headers[i];
        h.voxelsOverOne = static_cast<std::uint32_t>(tallies[i].voxelsOverOne);
        h.densitySum = tallies[i].densitySum;
        h.rawDensitySum = tallies[i].rawDensitySum;
        h.excessOverOne = tallies[i].excessOverOne;
    }
    return packed;
}

} // namespace

TEST_CASE("RegionWriter takes resolved, packed regions and writes what submit() writes", "[store]") {
    ScratchDir scratch;
    const std::vector<AccumulatorRegion> regions = makeAccumulatorRegions(16, 6);
    std::vector<BrickAccumulator> all;
    for (const auto& r : regions) all.insert(all.end(), r.accumulators.begin(), r.accumulators.end());
    const BrickVolume expected = resolveVolume(testGrid(), Reduce::Mean, Overlap::Clamp, all);

    SECTION("into a store, under a tiny bound") {
        const std::string dir = scratch.sub("w");
        {
            BrickStore store(dir, testManifest(), false);
            RegionWriter writer(store, Reduce::Mean, Overlap::Clamp, 1, 3);
            for (const auto& r : regions) writer.submitResolved(r.id, r.min, r.max, packOnCpu(r.accumulators));
            CHECK(writer.finish().size() == regions.size());
            const RegionWriterStats stats = writer.stats();
            CHECK(stats.bricksWritten == expected.bricks.size());
            CHECK(stats.tally.activeVoxels == expected.tally.activeVoxels);
            CHECK(stats.tally.densitySum == Approx(expected.tally.densitySum).epsilon(1e-12));
            CHECK(stats.tally.rawDensitySum == Approx(expected.tally.rawDensitySum).epsilon(1e-12));
            store.markComplete(regions.size());
        }
        const BrickVolume back = loadStore(dir);
        REQUIRE(back.bricks.size() == expected.bricks.size());
        std::size_t mismatches = 0;
        for (std::size_t i = 0; i < back.bricks.size(); ++i) mismatches += !sameBits(back.bricks[i], expected.bricks[i]);
        CHECK(mismatches == 0);
    }
    SECTION("to a destination") {
        std::mutex mutex;
        std::vector<VoxelBrick> got;
        RegionWriter writer([&](std::uint64_t, std::vector<VoxelBrick>&& bricks) {
            std::lock_guard lock(mutex);
            got.insert(got.end(), bricks.begin(), bricks.end());
        }, Reduce::Mean, Overlap::Clamp, std::size_t(1) << 20, 2);
        for (const auto& r : regions) writer.submitResolved(r.id, r.min, r.max, packOnCpu(r.accumulators));
        std::uint64_t active = 0;
        for (const RegionInfo& info : writer.finish()) active += info.activeVoxels;
        CHECK(active == expected.tally.activeVoxels);
        std::sort(got.begin(), got.end(), [](const VoxelBrick& a, const VoxelBrick& b) { return a.key < b.key; });
        REQUIRE(got.size() == expected.bricks.size());
        std::size_t mismatches = 0;
        for (std::size_t i = 0; i < got.size(); ++i) mismatches += !sameBits(got[i], expected.bricks[i]);
        CHECK(mismatches == 0);
    }
    SECTION("to a packed destination, which gets them as they came, unpacked nowhere") {
        std::mutex mutex;
        std::vector<VoxelBrick> got;
        std::size_t unpackedCalls = 0;
        RegionWriter writer(
            [&](std::uint64_t, std::vector<VoxelBrick>&&) {
                std::lock_guard lock(mutex);
                ++unpackedCalls;
            },
            [&](std::uint64_t, const PackedBricks& packed) {
                const std::vector<VoxelBrick> bricks = unpackBricks(packed);
                std::lock_guard lock(mutex);
                got.insert(got.end(), bricks.begin(), bricks.end());
            },
            Reduce::Mean, Overlap::Clamp, std::size_t(1) << 20, 2);
        for (const auto& r : regions) writer.submitResolved(r.id, r.min, r.max, packOnCpu(r.accumulators));
        std::uint64_t active = 0, bricks = 0;
        for (const RegionInfo& info : writer.finish()) {
            active += info.activeVoxels;
            bricks += info.brickCount;
        }
        CHECK(unpackedCalls == 0);
        CHECK(active == expected.tally.activeVoxels);
        CHECK(bricks == expected.bricks.size());
        const RegionWriterStats stats = writer.stats();
        CHECK(stats.tally.activeVoxels == expected.tally.activeVoxels);
        CHECK(stats.tally.densitySum == Approx(expected.tally.densitySum).epsilon(1e-12));
        CHECK(stats.bricksWritten == expected.bricks.size());
        std::sort(got.begin(), got.end(), [](const VoxelBrick& a, const VoxelBrick& b) { return a.key < b.key; });
        REQUIRE(got.size() == expected.bricks.size());
        std::size_t mismatches = 0;
        for (std::size_t i = 0; i < got.size(); ++i) mismatches += !sameBits(got[i], expected.bricks[i]);
        CHECK(mismatches == 0);
    }
    SECTION("each region packed into storage recycled from earlier ones, as the GL backend does") {
        std::mutex mutex;
        std::vector<VoxelBrick> got;
        // A one-byte bound holds one region at a time: a submit returns once
        // the region before it is unpacked, so its storage is there to reuse.
        RegionWriter writer([&](std::uint64_t, std::vector<VoxelBrick>&& bricks) {
            std::lock_guard lock(mutex);
            got.insert(got.end(), bricks.begin(), bricks.end());
        }, Reduce::Mean, Overlap::Clamp, 1, 2);
        std::size_t recycled = 0;
        for (const auto& r : regions) {
            PackedBricks storage = writer.recycledPackedBricks();
            REQUIRE(storage.headers.empty());
            REQUIRE(storage.voxels.empty());
            recycled += storage.voxels.capacity() > 0;
            const PackedBricks packed = packOnCpu(r.accumulators);
            storage.append(packed.headers.data(), packed.headers.size(), packed.voxels.data(), packed.voxels.size());
            writer.submitResolved(r.id, r.min, r.max, std::move(storage));
        }
        writer.finish();
        CHECK(recycled >= regions.size() - 2);
        std::sort(got.begin(), got.end(), [](const VoxelBrick& a, const VoxelBrick& b) { return a.key < b.key; });
        REQUIRE(got.size() == expected.bricks.size());
        std::size_t mismatches = 0;
        for (std::size_t i = 0; i < got.size(); ++i) mismatches += !sameBits(got[i], expected.bricks[i]);
        CHECK(mismatches == 0);
    }
    SECTION("a header that contradicts its voxels is a worker error") {
        BrickStore store(scratch.sub("w"), testManifest(), false);
        RegionWriter writer(store, Reduce::Mean, Overlap::Clamp, 1, 2);
        PackedBricks bad = packOnCpu(regions[0].accumulators);
        REQUIRE(!bad.headers.empty());
        bad.headers.back().activeCount += 1;
        writer.submitResolved(0, regions[0].min, regions[0].max, std::move(bad));
        CHECK_THAT(errorOf([&] { writer.finish(); }), Catch::Contains("packed brick"));
    }
}

TEST_CASE("A RegionWriter worker error surfaces from submit and finish, without deadlock", "[store]") {
    ScratchDir scratch;
    const std::string dir = scratch.sub("w");
    const std::vector<AccumulatorRegion> regions = makeAccumulatorRegions(6, 3);
    BrickStore store(dir, testManifest(), false);
    fs::remove_all(dir); // every write now fails

    SECTION("tiny bound: the second submit waits for the first region, then sees its error") {
        RegionWriter writer(store, Reduce::Mean, Overlap::Clamp, 1, 2);
        writer.submit(regions[0].id, regions[0].min, regions[0].max, regions[0].accumulators);
        const AccumulatorRegion& next = regions[1];
        CHECK_THAT(errorOf([&] { writer.submit(next.id, next.min, next.max, next.accumulators); }),
                   Catch::Contains("cannot write") && Catch::Contains("region-0.yvb"));
        CHECK_THROWS_AS(writer.finish(), Error);
    }
    SECTION("large bound: everything queued, finish reports the error") {
        RegionWriter writer(store, Reduce::Mean, Overlap::Clamp, std::size_t(1) << 30, 2);
        for (const auto& r : regions) {
            try {
                writer.submit(r.id, r.min, r.max, r.accumulators);
            } catch (const Error&) {
            }
        }
        CHECK_THAT(errorOf([&] { writer.finish(); }), Catch::Contains("cannot write"));
    }
    SECTION("a malformed accumulator is refused in the caller's thread") {
        RegionWriter writer(store, Reduce::Mean, Overlap::Clamp, 1);
        std::vector<BrickAccumulator> bad(1);
        bad[0].words.resize(kMaxWords * kBrickVoxels);
        CHECK_THAT(errorOf([&] { writer.submit(9, kAll0, kAll1, bad); }), Catch::Contains("words"));
    }
}

namespace {

struct VdbGrids {
    openvdb::FloatGrid::Ptr density;
    openvdb::Vec3SGrid::Ptr orientation;
    openvdb::MetaMap::Ptr meta;
};

VdbGrids readVdb(const std::string& path) {
    openvdb::initialize();
    openvdb::io::File file(path);
    file.open();
    VdbGrids g{openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("density")),
               openvdb::gridPtrCast<openvdb::Vec3SGrid>(file.readGrid("orientation")), file.getMetadata()};
    file.close();
    return g;
}

/// Voxels active in `a` but not in `b` with the same value.
template <class GridT>
std::size_t voxelsMissingFrom(const GridT& a, const GridT& b) {
    std::size_t missing = 0;
    auto acc = b.getConstAccessor();
    for (auto it = a.cbeginValueOn(); it; ++it)
        missing += !acc.isValueOn(it.getCoord()) || acc.getValue(it.getCoord()) != *it;
    return missing;
}

/// A real volume (CPU voxelizer) split into two brick-aligned regions along x.
BrickVolume realVolume() {
    SliceOptions opt;
    opt.radius = 0.2;
    opt.twist = 1.0;
    const SlicePlan plan = planSlices(test::straightYarn({0.5, -0.25, 1}, {1, 0.3, 0.1}, 4), opt);
    return voxelizeCpu(plan, makeFiberCrossSection(), makeGrid(plan, 64, 0.0), VoxelizeSettings{});
}

void writeSplit(BrickStore& store, const BrickVolume& volume, int splitX) {
    std::vector<VoxelBrick> left, right;
    for (const VoxelBrick& b : volume.bricks) (brickCoord(b.key).x * 8 < splitX ? left : right).push_back(b);
    REQUIRE(!left.empty());
    REQUIRE(!right.empty());
    const glm::ivec3 dims = volume.grid.dims;
    store.writeRegion(0, {0, 0, 0}, {splitX, dims.y, dims.z}, left);
    store.writeRegion(1, {splitX, 0, 0}, dims, right);
}

} // namespace

TEST_CASE("Merging a store writes the same .vdb as writeVdb of the same bricks", "[store][vdb]") {
    ScratchDir scratch;
    const std::string dir = scratch.sub("w");
    const BrickVolume volume = realVolume();
    REQUIRE(volume.bricks.size() > 4);
    const int splitX = (volume.grid.dims.x / 16) * 8;
    StoreManifest m;
    m.fingerprint = 5;
    m.grid = volume.grid;
    m.reduce = volume.reduce;
    VolumeMetadata meta;
    meta.input = "straight";
    meta.backend = "cpu";
    meta.resolution = 64;

    const std::string direct = scratch.sub("direct.vdb"), merged = scratch.sub("merged.vdb");
    VolumeMetadata withRegions = meta; // the merge records the store's regions: writeVdb is given them
    {
        BrickStore store(dir, m, false);
        writeSplit(store, volume, splitX);
        CHECK_THAT(errorOf([&] { mergeStoreToVdb(store, merged, meta); }), Catch::Contains("has not finished"));
        store.markComplete(2);
        mergeStoreToVdb(store, merged, meta);
        withRegions.regions = recordedRegions(store.listRegions());
    }
    REQUIRE(withRegions.regions.size() == 2);
    writeVdb(direct, volume, withRegions);
    CHECK_FALSE(fs::exists(merged + ".partial"));

    const VdbGrids a = readVdb(direct), b = readVdb(merged);
    REQUIRE(b.density);
    REQUIRE(b.orientation);
    CHECK(b.density->activeVoxelCount() == volume.activeVoxelCount());
    CHECK(b.density->activeVoxelCount() == a.density->activeVoxelCount());
    CHECK(b.orientation->activeVoxelCount() == a.orientation->activeVoxelCount());
    CHECK(b.density->tree().leafCount() == a.density->tree().leafCount());
    CHECK(voxelsMissingFrom(*a.density, *b.density) == 0);
    CHECK(voxelsMissingFrom(*b.density, *a.density) == 0);
    CHECK(voxelsMissingFrom(*a.orientation, *b.orientation) == 0);
    CHECK(voxelsMissingFrom(*b.orientation, *a.orientation) == 0);
    CHECK(b.density->transform() == a.density->transform());
    CHECK(b.orientation->transform() == a.density->transform());
    CHECK(b.density->getGridClass() == openvdb::GRID_FOG_VOLUME);
    CHECK(b.meta->str() == a.meta->str());

    // The whole file, OpenVDB's random UUID aside, is the same, whatever the thread count.
    CHECK(test::vdbBytesWithoutUuid(merged) == test::vdbBytesWithoutUuid(direct));
    const std::string serial = scratch.sub("serial.vdb");
    {
        tbb::global_control oneThread(tbb::global_control::max_allowed_parallelism, 1);
        mergeStoreToVdb(dir, serial, meta);
    }
    CHECK(test::vdbBytesWithoutUuid(serial) == test::vdbBytesWithoutUuid(merged));

    const BrickVolume loaded = loadStore(dir);
    REQUIRE(loaded.bricks.size() == volume.bricks.size());
    std::size_t mismatches = 0;
    for (std::size_t i = 0; i < loaded.bricks.size(); ++i) mismatches += !sameBits(loaded.bricks[i], volume.bricks[i]);
    CHECK(mismatches == 0);
    CHECK(loaded.grid.dims == volume.grid.dims);
}

TEST_CASE("Merge refuses damaged, missing and overlapping regions", "[store][vdb]") {
    ScratchDir scratch;
    const std::string dir = scratch.sub("w"), out = scratch.sub("out.vdb");
    const BrickVolume volume = realVolume();
    const int splitX = (volume.grid.dims.x / 16) * 8;
    StoreManifest m;
    m.fingerprint = 6;
    m.grid = volume.grid;
    m.reduce = volume.reduce;
    {
        BrickStore store(dir, m, false);
        writeSplit(store, volume, splitX);
        store.markComplete(2);
    }

    SECTION("a damaged region") {
        std::vector<std::uint8_t> bytes = fileBytes(dir + "/region-1.yvb");
        bytes[bytes.size() - 10] ^= 1;
        putFile(dir + "/region-1.yvb", bytes);
        CHECK_THAT(errorOf([&] { mergeStoreToVdb(dir, out, {}); }),
                   Catch::Contains("region-1.yvb") && Catch::Contains("checksum mismatch"));
    }
    SECTION("a missing region") {
        fs::remove(dir + "/region-0.yvb");
        CHECK_THAT(errorOf([&] { mergeStoreToVdb(dir, out, {}); }), Catch::Contains("1 region files are on disk"));
    }
    SECTION("two regions holding the same brick") {
        {
            BrickStore store(dir, m, true);
            store.writeRegion(1, {0, 0, 0}, volume.grid.dims, {volume.bricks.front()});
        }
        CHECK_THAT(errorOf([&] { mergeStoreToVdb(dir, out, {}); }),
                   Catch::Contains("given twice") && Catch::Contains("region-0.yvb") &&
                       Catch::Contains("region-1.yvb"));
        CHECK_THAT(errorOf([&] { loadStore(dir); }), Catch::Contains("held by both"));
    }
    CHECK_FALSE(fs::exists(out));
    CHECK_FALSE(fs::exists(out + ".partial"));
}

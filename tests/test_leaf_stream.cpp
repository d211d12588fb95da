// Level 0's leaves written into the .vdb while regions still come
// (VdbAssembler::streamRegions, vdb/leaf_stream.h): the file OpenVDB reads
// holds the grids the whole-file writer gives, every checksum holds, the
// records reach the disk before write(), and whatever breaks the regions'
// order makes the file be written whole instead.
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json_fields.h"
#include "vdb/grid_checksums.h"
#include "vdb/leaf_batches.h"
#include "vdb/leaf_records.h"
#include "vdb/leaf_stream.h"
#include "vdb/tree_order.h"
#include "vdb/vdb_index.h"
#include "vdb/vdb_writer.h"
#include "byte_pattern.h"
#include "run_cli.h"
#include "test_helpers.h"
#include "vdb_bytes.h"

#include <catch2/catch.hpp>
#include <openvdb/openvdb.h>

#include <sys/stat.h>

#include <algorithm>
#include <numeric>
#include <cerrno>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <random>
#include <span>
#include <thread>

using namespace yv;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) { return yv::test::processScratchDir("yv_leaf_stream_test") / name; }

/// Regions of 32^3 bricks (256 voxels) over a grid past one root child on
/// every axis, each with its bricks (random places, masks and values).
struct RegionVolume {
    BrickVolume volume;
    std::map<std::uint64_t, std::vector<VoxelBrick>> regions; ///< by the tree order key of the region's lowest brick
};

RegionVolume regionVolume(int bricks) {
    RegionVolume out;
    BrickVolume& volume = out.volume;
    volume.grid.dims = {4600, 4300, 4400};
    volume.grid.voxelSize = 0.25;
    volume.grid.origin = {-1.0, 2.0, 0.5};
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), axis(-1.0f, 1.0f);
    std::map<std::uint64_t, VoxelBrick> byKey;
    for (int n = 0; n < bricks; ++n) {
        // Clustered, so that regions hold many bricks and some none.
        const glm::ivec3 c(int(rng() % 4) * 150 + int(rng() % 40), int(rng() % 4) * 130 + int(rng() % 40),
                           int(rng() % 4) * 135 + int(rng() % 40));
        VoxelBrick b;
        b.key = brickKey(c);
        for (int v = 0; v < kBrickVoxels; ++v) {
            if (n % 3 != 0 && rng() % 4 != 0) continue;
            b.activeMask[v >> 6] |= std::uint64_t(1) << (v & 63);
            b.density[v] = unit(rng) + 1e-6f;
            b.orientation[v] = glm::vec3(axis(rng), axis(rng), axis(rng));
        }
        byKey[b.key] = b;
    }
    for (const auto& [key, b] : byKey) {
        volume.bricks.push_back(b);
        const glm::ivec3 regionMin = brickCoord(key) / 32 * 32;
        out.regions[treeOrderKey(regionMin)].push_back(b);
    }
    return out;
}

VolumeMetadata someMetadata() {
    VolumeMetadata meta;
    meta.input = "regions test volume";
    meta.backend = "cpu";
    meta.resolution = 4600;
    return meta;
}

/// Every value of every grid both files share, read back through OpenVDB, is the same.
void checkSameGrids(const fs::path& a, const fs::path& b) {
    openvdb::io::File fa(a.string()), fb(b.string());
    fa.open();
    fb.open();
    const openvdb::GridPtrVecPtr ga = fa.getGrids(), gb = fb.getGrids();
    REQUIRE(ga->size() == gb->size());
    for (std::size_t n = 0; n < ga->size(); ++n) {
        const openvdb::GridBase::Ptr x = (*ga)[n], y = (*gb)[n];
        INFO(x->getName());
        CHECK(x->getName() == y->getName());
        CHECK(x->transform() == y->transform());
        CHECK(x->baseTree().activeVoxelCount() == y->baseTree().activeVoxelCount());
        if (auto dx = openvdb::gridPtrCast<openvdb::FloatGrid>(x)) {
            auto dy = openvdb::gridPtrCast<openvdb::FloatGrid>(y);
            REQUIRE(dy);
            CHECK(dx->tree().hasSameTopology(dy->tree()));
            auto acc = dy->getConstAccessor();
            std::size_t differ = 0;
            for (auto it = dx->cbeginValueOn(); it; ++it) differ += acc.getValue(it.getCoord()) != *it;
            CHECK(differ == 0);
        } else {
            auto vx = openvdb::gridPtrCast<openvdb::Vec3SGrid>(x), vy = openvdb::gridPtrCast<openvdb::Vec3SGrid>(y);
            REQUIRE(vx);
            REQUIRE(vy);
            CHECK(vx->tree().hasSameTopology(vy->tree()));
            auto acc = vy->getConstAccessor();
            std::size_t differ = 0;
            for (auto it = vx->cbeginValueOn(); it; ++it) differ += acc.getValue(it.getCoord()) != *it;
            CHECK(differ == 0);
        }
    }
}

/// The bytes on disk of the one temporary beside `out` (its .partial file).
std::uint64_t partialBytesOnDisk(const fs::path& out) {
    for (const auto& e : fs::directory_iterator(out.parent_path()))
        if (e.path().filename().string().rfind(out.filename().string() + ".partial", 0) == 0) {
            struct stat st {};
            if (::stat(e.path().c_str(), &st) == 0) return std::uint64_t(st.st_blocks) * 512;
        }
    return 0;
}

/// The regions' first tree order keys, in order.
std::vector<std::uint64_t> firstOrders(const RegionVolume& v) {
    std::vector<std::uint64_t> orders;
    for (const auto& [order, bricks] : v.regions) orders.push_back(order);
    return orders;
}

} // namespace

TEST_CASE("Leaves streamed while regions finish give the grids and checksums of the file written whole",
          "[vdb][stream][leafstream]") {
    openvdb::initialize();
    const RegionVolume v = regionVolume(3000);
    REQUIRE(v.regions.size() > 20);
    const fs::path whole = scratch("whole.vdb"), streamed = scratch("streamed.vdb");
    for (VdbPrecision p : {VdbPrecision::Float, VdbPrecision::Half})
        for (int lod : {0, 5}) {
            INFO(toString(p) << ", lod to " << lod);
            VdbWriteOptions options;
            options.precision = p;
            options.lodLevels = lod;
            options.lodFirstLevel = lod ? 3 : 1;
            options.outputChunkBytes = 16384; // many chunks, cut through records and blocks
            writeVdb(whole.string(), v.volume, someMetadata(), options);

            VdbWriteTimings timings;
            options.timings = &timings;
            VdbAssembler assembler(streamed.string(), v.volume.grid, v.volume.reduce, options);
            REQUIRE(assembler.streamRegions(firstOrders(v))); // the scratch directory is on ext4 or XFS
            // The regions finish in any order, several at once, each after its bricks are in.
            std::vector<std::size_t> finishOrder(v.regions.size());
            for (std::size_t i = 0; i < finishOrder.size(); ++i) finishOrder[i] = i;
            std::shuffle(finishOrder.begin(), finishOrder.end(), std::mt19937(5));
            std::vector<const std::vector<VoxelBrick>*> bricksOf;
            for (const auto& [order, bricks] : v.regions) bricksOf.push_back(&bricks);
            std::vector<std::thread> threads;
            for (int t = 0; t < 3; ++t)
                threads.emplace_back([&, t] {
                    for (std::size_t k = std::size_t(t); k < finishOrder.size(); k += 3) {
                        const std::size_t r = finishOrder[k];
                        assembler.add(*bricksOf[r], "region " + std::to_string(r));
                        assembler.regionDone(r);
                    }
                });
            for (std::thread& t : threads) t.join();
            CHECK(assembler.brickCount() == v.volume.bricks.size());
            assembler.write(someMetadata());
            CHECK(timings.streamedBytes > 0);

            checkSameGrids(streamed, whole);
            // A few zero bytes before each of level 0's grids' data, no more: the holes are gone.
            const std::uint64_t a = fs::file_size(streamed), b = fs::file_size(whole);
            CHECK(a >= b);
            CHECK(a < b + 2 * 65536);
            // yarnvox's own reader: every checksum, and every leaf of level 0.
            const VdbIndex index(streamed.string());
            CHECK(verifyGridChecksums(index) == index.gridCount());
            REQUIRE(index.inSubset());
            const VdbGridInfo* g = index.grid("density");
            REQUIRE(g);
            const VdbLeafTable table = index.leaves(*g);
            REQUIRE(table.bricks.size() == v.volume.bricks.size());
            std::vector<std::uint8_t> bytes;
            readLeafRecords(index, *g, table, 0, table.bricks.size(), bytes);
            std::map<std::uint64_t, const VoxelBrick*> given;
            for (const VoxelBrick& b : v.volume.bricks) given[b.key] = &b;
            std::size_t differ = 0;
            std::vector<float> values(kBrickVoxels);
            for (std::size_t leaf = 0; leaf < table.bricks.size(); ++leaf) {
                const std::uint64_t at = table.records[leaf];
                decodeLeafRecord(std::span(bytes).subspan(at - table.records[0], table.records[leaf + 1] - at), index, *g,
                                 leaf, table.bricks[leaf], at, values.data());
                const VoxelBrick& brick = *given.at(brickKey(table.bricks[leaf]));
                for (int x = 0; x < kBrickVoxels; ++x) // both in OpenVDB's voxel order
                    differ += values[x] != (brick.isActive(x) ? (p == VdbPrecision::Half ? float(openvdb::math::half(brick.density[x])) : brick.density[x]) : 0.0f);
            }
            CHECK(differ == 0);
        }
    fs::remove(whole);
    fs::remove(streamed);
}

TEST_CASE("Streamed leaf records reach the disk before the file is finished", "[vdb][stream][leafstream]") {
    const RegionVolume v = regionVolume(3000);
    const fs::path out = scratch("early.vdb");
    VdbAssembler assembler(out.string(), v.volume.grid, v.volume.reduce);
    REQUIRE(assembler.streamRegions(firstOrders(v)));
    // All regions but the last: every leaf before the last region's corner is final.
    std::size_t r = 0, added = 0;
    for (const auto& [order, bricks] : v.regions) {
        if (r + 1 == v.regions.size()) break;
        assembler.add(bricks);
        assembler.regionDone(r++);
        added += bricks.size();
    }
    const std::uint64_t early = 512 * added; // at least a byte a voxel... of a few leaves' worth
    std::uint64_t onDisk = 0;
    for (int wait = 0; wait < 500 && onDisk < early; ++wait) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        onDisk = partialBytesOnDisk(out);
    }
    CHECK(onDisk >= early);
    assembler.add(v.regions.rbegin()->second);
    assembler.regionDone(r);
    assembler.write(someMetadata());
    CHECK(fs::exists(out));
    fs::remove(out);
}

TEST_CASE("A brick out of its region's order ends the stream, and the file is written whole", "[vdb][stream][leafstream]") {
    openvdb::initialize();
    const RegionVolume v = regionVolume(1500);
    const fs::path whole = scratch("order-whole.vdb"), streamed = scratch("order-streamed.vdb");
    writeVdb(whole.string(), v.volume, someMetadata());
    {
        VdbAssembler assembler(streamed.string(), v.volume.grid, v.volume.reduce);
        REQUIRE(assembler.streamRegions(firstOrders(v)));
        // Region 0's bricks all come with the last region: after the frontier passed them.
        std::size_t r = 0;
        for (const auto& [order, bricks] : v.regions) {
            if (r > 0) assembler.add(bricks);
            if (r == 0) assembler.regionDone(r);
            else if (r + 1 < v.regions.size()) assembler.regionDone(r);
            ++r;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(100)); // let the stream pass region 0
        assembler.add(v.regions.begin()->second);
        assembler.regionDone(r - 1);
        assembler.write(someMetadata());
    }
    checkSameGrids(streamed, whole);
    // Written whole: OpenVDB's layout, the whole writer's bytes.
    const bool sameBytes = test::vdbBytesWithoutUuid(streamed) == test::vdbBytesWithoutUuid(whole);
    CHECK(sameBytes);
    fs::remove(whole);
    fs::remove(streamed);
}

TEST_CASE("A brick given twice in two streamed regions is refused and leaves no file", "[vdb][stream][leafstream]") {
    const RegionVolume v = regionVolume(1500);
    const fs::path out = scratch("stream-twice.vdb");
    fs::remove(out);
    {
        VdbAssembler assembler(out.string(), v.volume.grid, v.volume.reduce);
        REQUIRE(assembler.streamRegions(firstOrders(v)));
        std::size_t r = 0;
        for (const auto& [order, bricks] : v.regions) {
            assembler.add(bricks, "region " + std::to_string(r));
            if (r == 3) assembler.add(std::span(bricks).first(1), "region 3 again");
            assembler.regionDone(r++);
        }
        try {
            assembler.write(someMetadata());
            FAIL("no error");
        } catch (const Error& e) {
            CHECK(std::string(e.what()).find("given twice (from region 3") != std::string::npos);
        }
    }
    CHECK_FALSE(fs::exists(out));
    for (const auto& e : fs::directory_iterator(out.parent_path()))
        CHECK(e.path().filename().string().rfind("stream-twice.vdb.partial", 0) != 0);
}

TEST_CASE("voxelize with YV_STREAM_LEAVES=0 writes the leaves after the run, the same grids, and a bad value is one line",
          "[cli][leafstream]") {
    openvdb::initialize();
    const fs::path bcc = scratch("stream-leaves.bcc");
    REQUIRE(test::runYarnvox("gen --pattern twill --shape cylinder --crossings 400 -o " + bcc.string()).exitCode == 0);
    const auto voxelize = [&](const std::string& value, const fs::path& vdb, const fs::path& stats) {
        fs::remove(vdb);
        return test::runShell("YV_STREAM_LEAVES=" + value + " " + std::string(YV_BINARY_DIR) + "/yarnvox voxelize " +
                              bcc.string() + " -o " + vdb.string() +
                              " --backend cpu --resolution 128 --fragment-budget 20000 --quiet --stats " + stats.string());
    };
    const fs::path streamed = scratch("streamed-cli.vdb"), after = scratch("after-cli.vdb");
    const fs::path streamedStats = scratch("streamed.json"), afterStats = scratch("after.json");
    REQUIRE(voxelize("1", streamed, streamedStats).exitCode == 0);
    REQUIRE(voxelize("0", after, afterStats).exitCode == 0);
    const auto statsOf = [](const fs::path& path) {
        std::ifstream in(path);
        return Json::parse(in);
    };
    const Json a = statsOf(streamedStats), b = statsOf(afterStats);
    CHECK(b["vdb_streamed_bytes"].get<std::uint64_t>() == 0);
    // The scratch directory is on ext4 or XFS, which cut the holes out.
    CHECK(a["vdb_streamed_bytes"].get<std::uint64_t>() > 0);
    CHECK(a["backend_stats"]["zoom_regions"].get<std::uint64_t>() > 4);
    CHECK(a["active_voxels"] == b["active_voxels"]);
    const std::uint64_t sizeStreamed = fs::file_size(streamed), sizeAfter = fs::file_size(after);
    CHECK(sizeStreamed >= sizeAfter);
    CHECK(sizeStreamed < sizeAfter + 2 * 65536); // zeros before two grids' data, no holes
    // The same grids, voxel by voxel, through OpenVDB; yarnvox's own checks of the file hold.
    checkSameGrids(streamed, after);
    CHECK(test::runYarnvox("inspect " + streamed.string() + " --verify").exitCode == 0);
    for (const char* bad : {"2", "yes", "", "-1"}) {
        const test::RunResult r = voxelize(bad, after, afterStats);
        INFO(bad << ": " << r.output);
        CHECK(r.exitCode != 0);
        CHECK(r.output.find(std::string("YV_STREAM_LEAVES=") + bad + ": not a count of switches (0: off, 1: on) (0 to 1)") !=
              std::string::npos);
        CHECK_FALSE(fs::exists(after));
    }
}

TEST_CASE("One region's leaves are not streamed: the file is OpenVDB's layout", "[vdb][stream][leafstream]") {
    const RegionVolume v = regionVolume(600);
    const fs::path whole = scratch("one-whole.vdb"), one = scratch("one-region.vdb");
    writeVdb(whole.string(), v.volume, someMetadata());
    {
        VdbAssembler assembler(one.string(), v.volume.grid, v.volume.reduce);
        CHECK_FALSE(assembler.streamRegions({0}));
        assembler.add(v.volume.bricks);
        assembler.regionDone(0); // ignored where nothing streams
        assembler.write(someMetadata());
    }
    const bool sameBytes = test::vdbBytesWithoutUuid(one) == test::vdbBytesWithoutUuid(whole);
    CHECK(sameBytes);
    fs::remove(whole);
    fs::remove(one);
}

TEST_CASE("voxelize stopped by a signal while its leaves stream keeps neither the .vdb nor a temporary", "[cli][leafstream][signals]") {
    const fs::path dir = scratch("stopped");
    fs::create_directories(dir);
    const fs::path bcc = dir / "g.bcc", out = dir / "out.vdb";
    REQUIRE(test::runYarnvox("gen --pattern twill --shape cylinder --crossings 400 -o " + bcc.string()).exitCode == 0);
    for (const std::string point : {"stream-leaves", "stream-leaves:TERM"}) {
        INFO(point);
        const test::RunResult r = test::runShell("YARNVOX_TEST_SIGNAL_AT=" + point + " " + std::string(YV_BINARY_DIR) +
                                                 "/yarnvox voxelize " + bcc.string() + " -o " + out.string() +
                                                 " --backend cpu --resolution 128 --fragment-budget 20000 --quiet");
        INFO(r.output);
        CHECK(r.exitCode == 1);
        CHECK(r.output.find(point.ends_with(":TERM") ? "interrupted by SIGTERM" : "interrupted by SIGINT") != std::string::npos);
        CHECK_FALSE(fs::exists(out));
        std::size_t others = 0;
        for (const auto& e : fs::directory_iterator(dir)) others += e.path() != bcc;
        CHECK(others == 0); // no .partial file, no scratch file
    }
    fs::remove_all(dir);
}

TEST_CASE("A stream whose write fails says why at the next region's leaves, not after the last", "[vdb][leafstream]") {
    const fs::path out = scratch("full.vdb");
    PendingFile file(out.string());
    // A disk that is full: every write refused.
    ChunkedOutput output(file.fd(), "test output", 0, [](int, const void*, std::size_t, off_t) -> ssize_t {
        errno = ENOSPC;
        return -1;
    });
    const std::optional<StreamLanes> lanes = planStreamLanes(file.fd(), 1);
    REQUIRE(lanes); // the scratch directory is on ext4 or XFS
    SpillFile spill(out.parent_path().string(), "the test's scratch file");
    const std::uint64_t at = spill.append(std::vector<std::uint8_t>(100000, 7));
    LeafStream stream(spill, output, 1, *lanes, {0, 1000});
    std::vector<LeafRecord> leaves(20);
    for (std::size_t i = 0; i < leaves.size(); ++i) {
        leaves[i].order = i;
        leaves[i].at[0] = at + 5000 * i;
        leaves[i].bytes[0] = 5000;
    }
    stream.add(std::move(leaves));
    stream.regionDone(0); // region 0's leaves are final: the stream writes them, and fails
    std::string said;
    for (int wait = 0; wait < 500 && said.empty(); ++wait) {
        try {
            stream.add({});
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        } catch (const Error& e) {
            said = e.what();
        }
    }
    CHECK(said == "test output: No space left on device");
    CHECK_THROWS_WITH(stream.finish(), "test output: No space left on device");
}

TEST_CASE("finalLeaves gives every leaf in tree order while the stream still writes and nothing when they are not in order",
          "[vdb][leafstream]") {
    const fs::path out = scratch("final.vdb");
    PendingFile file(out.string());
    ChunkedOutput output(file.fd(), "test output", 0);
    const std::optional<StreamLanes> lanes = planStreamLanes(file.fd(), 1);
    REQUIRE(lanes); // the scratch directory is on ext4 or XFS
    SpillFile spill(out.parent_path().string(), "the test's scratch file");
    const std::uint64_t at = spill.append(test::bytePattern(200000, 5));
    const auto region = [&](std::uint64_t from, std::uint64_t count) {
        std::vector<LeafRecord> leaves(count);
        for (std::size_t i = 0; i < leaves.size(); ++i) {
            leaves[i].order = from + i;
            leaves[i].at[0] = at + 4000 * (from + i);
            leaves[i].bytes[0] = 4000;
        }
        return leaves;
    };
    SECTION("in order: the same leaves as finish() hands over") {
        LeafStream stream(spill, output, 1, *lanes, {0, 10, 20});
        stream.add(region(0, 10));
        stream.regionDone(0); // streamed while the others come
        stream.add(region(20, 15));
        stream.add(region(10, 10));
        stream.regionDone(2);
        stream.regionDone(1);
        const std::optional<std::vector<LeafRecord>> leaves = stream.finalLeaves();
        REQUIRE(leaves);
        std::vector<std::uint64_t> orders;
        for (const LeafRecord& r : *leaves) orders.push_back(r.order);
        std::vector<std::uint64_t> expected(35);
        std::iota(expected.begin(), expected.end(), 0);
        CHECK(orders == expected);
        const LeafStream::Result result = stream.finish();
        REQUIRE(result.intact);
        CHECK(result.leaves.empty()); // handed over, not copied
        // Every whole block of the records streamed, each as the scratch space holds it.
        REQUIRE(result.streamedBytes[0] == 35 * 4000 / kChecksumBlockBytes * kChecksumBlockBytes);
        std::vector<std::uint8_t> lane(result.streamedBytes[0]);
        std::ifstream written(file.temporaryPath(), std::ios::binary);
        written.seekg(std::streamoff(lanes->laneAt[0]));
        REQUIRE(written.read(reinterpret_cast<char*>(lane.data()), std::streamsize(lane.size())));
        std::vector<std::uint8_t> records(lane.size());
        spill.read(at, records);
        CHECK(lane == records);
    }
    SECTION("a brick given twice: nothing, and finish() says the stream is not intact") {
        LeafStream stream(spill, output, 1, *lanes, {0, 10});
        stream.add(region(0, 10));
        stream.add(region(5, 10)); // 5 to 9 again
        stream.regionDone(1);
        stream.regionDone(0);
        CHECK_FALSE(stream.finalLeaves());
        CHECK_FALSE(stream.finish().intact);
    }
}

TEST_CASE("sortInTreeOrder and appendInTreeOrder put leaves in tree order, ties by batch and then by their place before", "[vdb][leafstream]") {
    std::mt19937_64 random(11);
    // Few orders and batches, so that ties are many; sizes on both sides of the key sort's threshold.
    for (std::size_t count : {std::size_t(0), std::size_t(1), std::size_t(300), std::size_t(4095), std::size_t(70001)}) {
        INFO(count << " leaves");
        std::vector<LeafRecord> leaves(count);
        for (std::size_t i = 0; i < count; ++i) {
            leaves[i].order = random() % (count / 4 + 1);
            leaves[i].source = std::uint32_t(random() % 3);
            leaves[i].at[0] = i; // who it was
            leaves[i].bytes[1] = std::uint32_t(random());
            leaves[i].mask[7] = random();
        }
        std::vector<LeafRecord> expected = leaves;
        std::stable_sort(expected.begin(), expected.end(), inTreeOrder);
        sortInTreeOrder(leaves);
        REQUIRE(leaves.size() == expected.size());
        bool same = true;
        for (std::size_t i = 0; i < count; ++i)
            same = same && leaves[i].at[0] == expected[i].at[0] && leaves[i].order == expected[i].order &&
                   leaves[i].bytes[1] == expected[i].bytes[1] && leaves[i].mask == expected[i].mask;
        CHECK(same);

        // The same leaves as pieces appended after others: each piece's leaves in the
        // pieces' order where they tie, after the leaves already there.
        std::vector<LeafRecord> original = expected;
        std::shuffle(original.begin(), original.end(), random);
        std::vector<std::span<const LeafRecord>> pieces;
        for (std::size_t from = 0; from < count;) {
            const std::size_t n = std::min<std::size_t>(count - from, 1 + random() % 9000);
            pieces.emplace_back(original.data() + from, n);
            from += n;
        }
        std::vector<LeafRecord> appended(5);
        for (std::size_t i = 0; i < appended.size(); ++i) appended[i].at[0] = 1000000 + i;
        appendInTreeOrder(pieces, appended);
        std::vector<LeafRecord> reference = original;
        std::stable_sort(reference.begin(), reference.end(), inTreeOrder);
        REQUIRE(appended.size() == count + 5);
        bool kept = true, sorted = true;
        for (std::size_t i = 0; i < 5; ++i) kept = kept && appended[i].at[0] == 1000000 + i;
        for (std::size_t i = 0; i < count; ++i)
            sorted = sorted && appended[5 + i].at[0] == reference[i].at[0] && appended[5 + i].mask == reference[i].mask;
        CHECK(kept);
        CHECK(sorted);
    }
}

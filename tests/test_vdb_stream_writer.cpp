// yarnvox's own .vdb writer against OpenVDB's: for the same grids, the same
// file bytes (but OpenVDB's random UUID), for every compression and precision.
#include "core/error.h"
#include "vdb/tree_order.h"
#include "vdb/vdb_writer.h"
#include "packed_test_bricks.h"
#include "test_helpers.h"
#include "vdb_bytes.h"

#include <catch2/catch.hpp>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <thread>

using namespace yv;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) { return yv::test::processScratchDir("yv_stream_test") / name; }

/// Bricks that exercise the tree: several root children (past voxel 4096 on
/// every axis), internal nodes with one and with many children, full leaves,
/// single voxels at both ends of a leaf, random masks and values (some of
/// them round in half precision), axes of any sign.
BrickVolume treeShapedVolume() {
    BrickVolume volume;
    volume.grid.dims = {5000, 4200, 4500};
    volume.grid.voxelSize = 0.37;
    volume.grid.origin = {-3.0, 1.5, 0.25};
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), axis(-1.0f, 1.0f);
    std::vector<glm::ivec3> coords;
    for (int x = 0; x < 3; ++x)
        for (int y = 0; y < 3; ++y)
            for (int z = 0; z < 2; ++z) coords.push_back({10 + x, 20 + y, 30 + z}); // one lower node, many leaves
    coords.push_back({0, 0, 0});
    coords.push_back({15, 15, 15});
    coords.push_back({16, 0, 0});   // next lower node
    coords.push_back({511, 3, 9});  // last brick of a root child
    coords.push_back({512, 3, 9});  // first of the next one
    coords.push_back({600, 520, 540});
    coords.push_back({3, 515, 1});
    for (int i = 0; i < 200; ++i)
        coords.push_back({int(rng() % 620), int(rng() % 520), int(rng() % 560)});
    std::sort(coords.begin(), coords.end(), [](glm::ivec3 a, glm::ivec3 b) { return brickKey(a) < brickKey(b); });
    coords.erase(std::unique(coords.begin(), coords.end()), coords.end());
    for (std::size_t n = 0; n < coords.size(); ++n) {
        VoxelBrick b;
        b.key = brickKey(coords[n]);
        for (int v = 0; v < kBrickVoxels; ++v) {
            bool on = false;
            switch (n % 4) {
            case 0: on = true; break;                            // full
            case 1: on = v == 0 || v == 511; break;              // both ends
            case 2: on = (rng() % 3) == 0; break;                // random
            default: on = v == int(n % kBrickVoxels); break;     // one voxel
            }
            if (!on) continue;
            b.activeMask[v >> 6] |= std::uint64_t(1) << (v & 63);
            b.density[v] = n % 5 == 0 ? 1.0f : unit(rng) + 1e-6f;
            b.orientation[v] = glm::vec3(axis(rng), axis(rng), axis(rng));
        }
        volume.bricks.push_back(b);
    }
    return volume;
}

openvdb::math::Transform::Ptr transformOf(const VoxelGrid& grid) {
    auto t = openvdb::math::Transform::createLinearTransform(grid.voxelSize);
    const glm::dvec3 c = grid.origin + 0.5 * grid.voxelSize;
    t->postTranslate(openvdb::Vec3d(c.x, c.y, c.z));
    return t;
}

/// Level `level`'s grids as OpenVDB trees, with the values `ours` holds
/// (test_lod.cpp checks those against a brute-force reduction; here the
/// file's bytes are what is compared) and the names, class, vector type,
/// level and transform (voxel size 2^L h, voxel (0, 0, 0) centred at the
/// grid's origin plus half of it) the test expects.
openvdb::GridPtrVec lodGridsFrom(const fs::path& ours, const VoxelGrid& grid, int level, bool half) {
    openvdb::io::File file(ours.string());
    file.open();
    const std::string suffix = "_lod" + std::to_string(level);
    auto readDensity = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("density" + suffix));
    auto readOrientation = openvdb::gridPtrCast<openvdb::Vec3SGrid>(file.readGrid("orientation" + suffix));
    file.close();
    REQUIRE(readDensity);
    REQUIRE(readOrientation);
    auto density = openvdb::FloatGrid::create(0.0f);
    auto orientation = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    for (auto it = readDensity->cbeginValueOn(); it; ++it) density->tree().setValueOn(it.getCoord(), *it);
    for (auto it = readOrientation->cbeginValueOn(); it; ++it) orientation->tree().setValueOn(it.getCoord(), *it);
    density->setName("density" + suffix);
    density->setGridClass(openvdb::GRID_FOG_VOLUME);
    orientation->setName("orientation" + suffix);
    orientation->setVectorType(openvdb::VEC_INVARIANT);
    const double h = grid.voxelSize * (1 << level);
    auto transform = openvdb::math::Transform::createLinearTransform(h);
    const glm::dvec3 c = grid.origin + 0.5 * h;
    transform->postTranslate(openvdb::Vec3d(c.x, c.y, c.z));
    for (openvdb::GridBase::Ptr g : {openvdb::GridBase::Ptr(density), openvdb::GridBase::Ptr(orientation)}) {
        g->insertMeta("lod_level", openvdb::Int32Metadata(level));
        g->setTransform(transform);
        g->setSaveFloatAsHalf(half);
    }
    return {density, orientation};
}

/// The same grids built as OpenVDB trees and written by OpenVDB's io::File,
/// with the file metadata of `ours` (whose serialisation is also compared);
/// with `lodLevels`, the pyramid's grids of levels lodFirst..lodLevels after
/// them (lodGridsFrom).
void writeWithOpenVdb(const fs::path& path, const BrickVolume& volume, const fs::path& ours, VdbCompression c,
                      bool half, int lodLevels = 0, int lodFirst = 1) {
    auto density = openvdb::FloatGrid::create(0.0f);
    auto orientation = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    for (const VoxelBrick& b : volume.bricks) {
        const glm::ivec3 o = brickCoord(b.key) * 8;
        for (int v = 0; v < kBrickVoxels; ++v)
            if (b.isActive(v)) {
                const openvdb::Coord xyz(o.x + (v >> 6), o.y + ((v >> 3) & 7), o.z + (v & 7));
                density->tree().setValueOn(xyz, b.density[v]);
                const glm::vec3 a = b.orientation[v];
                orientation->tree().setValueOn(xyz, openvdb::Vec3s(a.x, a.y, a.z));
            }
    }
    density->setName("density");
    density->setGridClass(openvdb::GRID_FOG_VOLUME);
    orientation->setName("orientation");
    orientation->setVectorType(openvdb::VEC_INVARIANT);
    const auto transform = transformOf(volume.grid);
    density->setTransform(transform);
    orientation->setTransform(transform);
    density->setSaveFloatAsHalf(half);
    orientation->setSaveFloatAsHalf(half);

    openvdb::io::File oursFile(ours.string());
    oursFile.open();
    const openvdb::MetaMap::Ptr meta = oursFile.getMetadata();
    oursFile.close();

    std::uint32_t flags = openvdb::io::COMPRESS_NONE;
    if (c == VdbCompression::Blosc) flags = openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK;
    if (c == VdbCompression::Zip) flags = openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK;
    if (c == VdbCompression::ActiveMask) flags = openvdb::io::COMPRESS_ACTIVE_MASK;
    openvdb::io::File file(path.string());
    file.setCompression(flags);
    openvdb::GridPtrVec grids{density, orientation};
    for (int level = lodFirst; level <= lodLevels; ++level)
        for (const openvdb::GridBase::Ptr& g : lodGridsFrom(ours, volume.grid, level, half)) grids.push_back(g);
    file.write(grids, *meta);
}

/// Every value of both files' grids, read back through OpenVDB, is the same.
void checkSameGrids(const fs::path& a, const fs::path& b, int lodLevels = 0, int lodFirst = 1) {
    openvdb::io::File fa(a.string()), fb(b.string());
    fa.open();
    fb.open();
    std::vector<std::string> names{"density", "orientation"};
    for (int level = lodFirst; level <= lodLevels; ++level)
        for (const char* base : {"density_lod", "orientation_lod"}) names.push_back(base + std::to_string(level));
    for (const std::string& name : names) {
        INFO(name);
        openvdb::GridBase::Ptr ga = fa.readGrid(name), gb = fb.readGrid(name);
        CHECK(ga->transform() == gb->transform());
        CHECK(ga->baseTree().activeVoxelCount() == gb->baseTree().activeVoxelCount());
        CHECK(ga->str() == gb->str()); // every metadata item, the class and the type
        CHECK(ga->saveFloatAsHalf() == gb->saveFloatAsHalf());
        if (auto da = openvdb::gridPtrCast<openvdb::FloatGrid>(ga)) {
            auto db = openvdb::gridPtrCast<openvdb::FloatGrid>(gb);
            CHECK(da->tree().hasSameTopology(db->tree()));
            auto acc = db->getConstAccessor();
            std::size_t differ = 0;
            for (auto it = da->cbeginValueOn(); it; ++it) differ += acc.getValue(it.getCoord()) != *it;
            CHECK(differ == 0);
        } else {
            auto oa = openvdb::gridPtrCast<openvdb::Vec3SGrid>(ga);
            auto ob = openvdb::gridPtrCast<openvdb::Vec3SGrid>(gb);
            REQUIRE(oa);
            CHECK(oa->tree().hasSameTopology(ob->tree()));
            auto acc = ob->getConstAccessor();
            std::size_t differ = 0;
            for (auto it = oa->cbeginValueOn(); it; ++it) differ += acc.getValue(it.getCoord()) != *it;
            CHECK(differ == 0);
        }
    }
}

/// Both files hold the same bytes (but OpenVDB's random UUID) and read back
/// as the same grids.
void checkSameFile(const fs::path& ours, const fs::path& theirs, int lodLevels = 0, int lodFirst = 1) {
    const auto a = test::vdbBytesWithoutUuid(ours), b = test::vdbBytesWithoutUuid(theirs);
    CHECK(a.size() == b.size());
    const auto mismatch = std::mismatch(a.begin(), a.end(), b.begin(), b.end());
    INFO("first difference at byte " << (mismatch.first - a.begin()));
    const bool sameBytes = a == b;
    CHECK(sameBytes);
    checkSameGrids(ours, theirs, lodLevels, lodFirst);
}

VolumeMetadata someMetadata() {
    VolumeMetadata meta;
    meta.input = "tree-shaped test volume";
    meta.backend = "cpu";
    meta.resolution = 5000;
    meta.sliceCount = 12345;
    meta.yarnRadius = 0.1;
    return meta;
}

} // namespace

TEST_CASE("Tree order follows OpenVDB's root, internal node and leaf order", "[vdb][stream]") {
    // Lexicographic by root child origin, then by child index inside each internal node.
    CHECK(treeOrderKey({0, 0, 1}) < treeOrderKey({0, 1, 0}));
    CHECK(treeOrderKey({15, 15, 15}) < treeOrderKey({0, 0, 16}));  // same upper node, lower node (0,0,1) after (0,0,0)
    CHECK(treeOrderKey({0, 1, 0}) < treeOrderKey({0, 0, 511})); // (0,0,511) lies in lower node (0,0,31)
    CHECK(treeOrderKey({511, 511, 511}) < treeOrderKey({0, 0, 512}));    // next root child along z comes later
    CHECK(treeOrderKey({0, 0, 512}) < treeOrderKey({0, 512, 0}));
    CHECK(treeOrderKey({0, 512, 0}) < treeOrderKey({512, 0, 0}));
    std::mt19937 rng(3);
    for (int i = 0; i < 1000; ++i) {
        const glm::ivec3 b(int(rng() % (1 << 21)), int(rng() % (1 << 21)), int(rng() % (1 << 21)));
        REQUIRE(treeOrderCoord(treeOrderKey(b)) == b);
    }
}

TEST_CASE("The streaming writer gives OpenVDB's own bytes for every compression and precision", "[vdb][stream]") {
    openvdb::initialize();
    const BrickVolume volume = treeShapedVolume();
    REQUIRE(volume.bricks.size() > 150);
    const fs::path ours = scratch("ours.vdb"), theirs = scratch("theirs.vdb");
    // Chunks of the output (vdb/chunked_output.h): one for the whole file,
    // and a page each, cutting through the topology and the leaf records.
    for (std::uint64_t chunk : {std::uint64_t(0), std::uint64_t(4096)}) {
        for (VdbCompression c : {VdbCompression::ActiveMask, VdbCompression::Blosc, VdbCompression::Zip, VdbCompression::None})
            for (VdbPrecision p : {VdbPrecision::Float, VdbPrecision::Half}) {
                INFO(toString(c) << ", " << toString(p) << ", chunks of " << chunk << " bytes");
                VdbWriteOptions options;
                options.compression = c;
                options.precision = p;
                options.outputChunkBytes = chunk;
                writeVdb(ours.string(), volume, someMetadata(), options);
                writeWithOpenVdb(theirs, volume, ours, c, p == VdbPrecision::Half);
                checkSameFile(ours, theirs);
            }
    }
    fs::remove(ours);
    fs::remove(theirs);
}

TEST_CASE("With --lod the file is OpenVDB's own for the same grids, for every compression and precision", "[vdb][stream][lod]") {
    openvdb::initialize();
    const BrickVolume volume = treeShapedVolume();
    const fs::path ours = scratch("lod-ours.vdb"), theirs = scratch("lod-theirs.vdb");
    // Every level 1..3 (--lod 3), and the preview's 3..5 (its lod_first_level
    // is in the file metadata OpenVDB is given).
    for (const auto& [first, last] : {std::pair(1, 3), std::pair(3, 5)})
        for (VdbCompression c : {VdbCompression::ActiveMask, VdbCompression::Blosc, VdbCompression::Zip, VdbCompression::None})
            for (VdbPrecision p : {VdbPrecision::Float, VdbPrecision::Half}) {
                INFO(toString(c) << ", " << toString(p) << ", levels " << first << " to " << last);
                VdbWriteOptions options;
                options.compression = c;
                options.precision = p;
                options.lodFirstLevel = first;
                options.lodLevels = last;
                options.outputChunkBytes = 8192; // chunks cut through every level's records
                writeVdb(ours.string(), volume, someMetadata(), options);
                writeWithOpenVdb(theirs, volume, ours, c, p == VdbPrecision::Half, last, first);
                checkSameFile(ours, theirs, last, first);
            }
    fs::remove(ours);
    fs::remove(theirs);
}

TEST_CASE("The streaming writer's empty volume is OpenVDB's empty volume", "[vdb][stream]") {
    openvdb::initialize();
    BrickVolume empty;
    empty.grid.dims = {8, 8, 8};
    empty.grid.voxelSize = 0.5;
    const fs::path ours = scratch("empty-ours.vdb"), theirs = scratch("empty-theirs.vdb");
    writeVdb(ours.string(), empty, someMetadata());
    writeWithOpenVdb(theirs, empty, ours, VdbCompression::ActiveMask, false);
    const bool sameBytes = test::vdbBytesWithoutUuid(ours) == test::vdbBytesWithoutUuid(theirs);
    CHECK(sameBytes);
    if (sameBytes) {
        fs::remove(ours);
        fs::remove(theirs);
    }
}

TEST_CASE("The streaming writer's bytes do not depend on batch order", "[vdb][stream]") {
    openvdb::initialize();
    const BrickVolume volume = treeShapedVolume();
    const fs::path whole = scratch("whole.vdb"), batches = scratch("batches.vdb");
    writeVdb(whole.string(), volume, someMetadata());
    {
        VdbAssembler assembler(batches.string(), volume.grid, volume.reduce);
        // Uneven batches, last first, from several threads.
        const std::span<const VoxelBrick> all(volume.bricks);
        std::vector<std::thread> threads;
        const std::size_t cuts[] = {0, 7, 8, 100, all.size()};
        for (int i = 3; i >= 0; --i)
            threads.emplace_back([&, i] { assembler.add(all.subspan(cuts[i], cuts[i + 1] - cuts[i]), "batch"); });
        for (std::thread& t : threads) t.join();
        CHECK(assembler.brickCount() == volume.bricks.size());
        assembler.write(someMetadata());
    }
    const bool sameBytes = test::vdbBytesWithoutUuid(whole) == test::vdbBytesWithoutUuid(batches);
    CHECK(sameBytes);
    fs::remove(whole);
    fs::remove(batches);
}

TEST_CASE("A brick given twice is refused and leaves no file", "[vdb][stream]") {
    const BrickVolume volume = treeShapedVolume();
    const fs::path out = scratch("twice.vdb");
    fs::remove(out);
    VdbAssembler assembler(out.string(), volume.grid, volume.reduce);
    assembler.add(volume.bricks, "region 1");
    assembler.add(std::span(volume.bricks).subspan(5, 1), "region 2");
    try {
        assembler.write(someMetadata());
        FAIL("no error");
    } catch (const Error& e) {
        CHECK(std::string(e.what()).find("given twice (from region 1 and region 2)") != std::string::npos);
    }
    CHECK_FALSE(fs::exists(out));
    for (const auto& e : fs::directory_iterator(out.parent_path()))
        CHECK(e.path().filename().string().rfind("twice.vdb.partial", 0) != 0);
}

TEST_CASE("Bricks added packed, as the GPU resolved them, give the file that voxel bricks give", "[vdb][stream]") {
    openvdb::initialize();
    BrickVolume volume = treeShapedVolume();
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const fs::path fromBricks = scratch("from-bricks.vdb"), fromPacked = scratch("from-packed.vdb");
    for (const bool albedo : {false, true}) {
        if (albedo)
            for (VoxelBrick& b : volume.bricks) {
                b.albedo.assign(kBrickVoxels, glm::vec3(0.0f));
                for (int v = 0; v < kBrickVoxels; ++v)
                    if (b.isActive(v)) b.albedo[v] = glm::vec3(unit(rng), unit(rng), unit(rng));
            }
        // Two batches of each, so the packed one's second batch starts past voxel 0.
        const std::size_t half = volume.bricks.size() / 2;
        const std::vector<VoxelBrick> first(volume.bricks.begin(), volume.bricks.begin() + std::ptrdiff_t(half));
        const std::vector<VoxelBrick> second(volume.bricks.begin() + std::ptrdiff_t(half), volume.bricks.end());
        for (VdbCompression c : {VdbCompression::ActiveMask, VdbCompression::Blosc, VdbCompression::Zip, VdbCompression::None})
            for (VdbPrecision p : {VdbPrecision::Float, VdbPrecision::Half})
                // No pyramid, every level 1..2, the preview's 3..4.
                for (const auto& [firstLevel, lod] : {std::pair(1, 0), std::pair(1, 2), std::pair(3, 4)}) {
                    INFO(toString(c) << ", " << toString(p) << ", levels " << firstLevel << " to " << lod << ", albedo " << albedo);
                    VdbWriteOptions options;
                    options.compression = c;
                    options.precision = p;
                    options.lodFirstLevel = firstLevel;
                    options.lodLevels = lod;
                    options.albedo = albedo;
                    {
                        VdbAssembler assembler(fromBricks.string(), volume.grid, volume.reduce, options);
                        assembler.add(first);
                        assembler.add(second);
                        assembler.write(someMetadata());
                    }
                    {
                        VdbAssembler assembler(fromPacked.string(), volume.grid, volume.reduce, options);
                        assembler.add(test::packBricks(first));
                        // The second batch's voxels behind others in their
                        // storage (as a region's passes append them), so its
                        // headers' firstVoxel is not 0.
                        const PackedBricks rest = test::packBricks(second);
                        PackedBricks behind = test::packBricks(first);
                        behind.headers.clear();
                        behind.append(rest.headers.data(), rest.headers.size(), rest.voxels.data(), rest.voxels.size(),
                                      albedo ? rest.albedo.data() : nullptr);
                        REQUIRE(behind.headers.front().firstVoxel > 0);
                        assembler.add(behind);
                        assembler.write(someMetadata());
                    }
                    const bool sameBytes = test::vdbBytesWithoutUuid(fromBricks) == test::vdbBytesWithoutUuid(fromPacked);
                    CHECK(sameBytes);
                }
    }
    fs::remove(fromBricks);
    fs::remove(fromPacked);
}

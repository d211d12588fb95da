// The preview pyramid (--lod preview, voxelize's default): its levels, read
// back through OpenVDB, against the same levels worked out here from level 0
// by the rule formats/vdb-subset.md states, voxel for voxel; the fibre
// volume per level; the metadata; and the option through the CLI.
#include "core/error.h"
#include "run_cli.h"
#include "test_helpers.h"
#include "vdb/lod_pyramid.h"
#include "vdb/lod_request.h"
#include "vdb/vdb_writer.h"
#include "vdb_bytes.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <thread>

using namespace yv;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) { return yv::test::processScratchDir("yv_lod_preview_test") / name; }

/// Bricks in a block that straddles level-3 to level-6 brick boundaries
/// (so parents gather children from several batches), lone bricks far apart,
/// random masks, densities, axes and (with `albedo`) colours.
BrickVolume previewVolume(unsigned seed, bool albedo) {
    BrickVolume volume;
    volume.grid.dims = {1024, 768, 512};
    volume.grid.voxelSize = 0.25;
    volume.grid.origin = {-1.0, 2.0, 0.5};
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), axis(-1.0f, 1.0f);
    std::vector<glm::ivec3> coords;
    for (int x = 5; x < 12; ++x)
        for (int y = 13; y < 19; ++y)
            for (int z = 6; z < 10; ++z) coords.push_back({x, y, z});
    coords.push_back({0, 0, 0});
    coords.push_back({127, 95, 63});
    for (int i = 0; i < 60; ++i) coords.push_back({int(rng() % 128), int(rng() % 96), int(rng() % 64)});
    std::sort(coords.begin(), coords.end(), [](glm::ivec3 a, glm::ivec3 b) { return brickKey(a) < brickKey(b); });
    coords.erase(std::unique(coords.begin(), coords.end()), coords.end());
    for (std::size_t n = 0; n < coords.size(); ++n) {
        VoxelBrick b;
        b.key = brickKey(coords[n]);
        if (albedo) b.albedo.assign(kBrickVoxels, glm::vec3(0.0f));
        for (int v = 0; v < kBrickVoxels; ++v) {
            // Some bricks full, some with holes, some with a voxel or two.
            if (n % 3 == 1 && rng() % 4 == 0) continue;
            if (n % 3 == 2 && rng() % 200 != 0) continue;
            b.activeMask[v >> 6] |= std::uint64_t(1) << (v & 63);
            b.density[v] = unit(rng) + 1e-3f;
            b.orientation[v] = glm::vec3(canonicalAxis(glm::normalize(glm::dvec3(axis(rng), axis(rng), axis(rng)))));
            if (albedo) b.albedo[v] = glm::vec3(unit(rng), unit(rng), unit(rng));
        }
        if (b.activeCount() > 0) volume.bricks.push_back(b);
    }
    return volume;
}

using Coord3 = std::array<int, 3>;

/// A coarse voxel as the rule makes it: the sums it is resolved from (as the
/// file's records round them) and what it resolves to.
struct HostVoxel {
    double densitySum = 0.0;
    std::array<double, 6> tensor{};
    std::array<double, 3> colourSum{};
    float density = 0.0f;
    glm::vec3 axis{0.0f}, albedo{0.0f};
};
using HostLevel = std::map<Coord3, HostVoxel>;

/// Sums rounded to the record's floats, then resolved: the mean over the
/// `voxelsBelow` voxels each covers, the tensor's principal axis, the
/// mass-weighted colour. Voxels whose mean rounds to 0 are left out.
void resolve(HostLevel& level, double voxelsBelow, bool albedo) {
    for (auto it = level.begin(); it != level.end();) {
        HostVoxel& c = it->second;
        for (double& t : c.tensor) t = double(float(t));
        for (double& k : c.colourSum) k = double(float(k));
        c.density = float(c.densitySum / voxelsBelow);
        if (!(c.density > 0.0f)) {
            it = level.erase(it);
            continue;
        }
        c.axis = glm::vec3(canonicalAxis(principalAxis(c.tensor.data())));
        if (albedo)
            for (int k = 0; k < 3; ++k) c.albedo[k] = float(std::min(1.0, c.colourSum[k] / c.densitySum));
        ++it;
    }
}

/// Level `first` (1 to 3: each of its voxels within one brick) from level 0,
/// summing each voxel's level-0 voxels in OpenVDB's voxel order as a brick's
/// record does.
HostLevel firstLevelFromBricks(const BrickVolume& volume, int first, bool albedo) {
    HostLevel level;
    for (const VoxelBrick& b : volume.bricks) {
        const glm::ivec3 o = brickCoord(b.key) * kBrickSize;
        for (int v = 0; v < kBrickVoxels; ++v) {
            if (!b.isActive(v)) continue;
            const glm::ivec3 p = o + glm::ivec3(v >> 6, (v >> 3) & 7, v & 7);
            HostVoxel& c = level[{p.x >> first, p.y >> first, p.z >> first}];
            const double d = b.density[v];
            const glm::dvec3 a(b.orientation[v]);
            c.densitySum += d;
            const double t[6] = {a.x * a.x, a.y * a.y, a.z * a.z, a.x * a.y, a.x * a.z, a.y * a.z};
            for (int i = 0; i < 6; ++i) c.tensor[i] += d * t[i];
            if (albedo)
                for (int k = 0; k < 3; ++k) c.colourSum[k] += d * b.albedo[v][k];
        }
    }
    resolve(level, double(1 << (3 * first)), albedo);
    return level;
}

/// The next level from `below`: each voxel from its 8 children as written
/// (density, tensor sums and colour as the file holds them), in OpenVDB's order.
HostLevel nextLevel(const HostLevel& below, bool albedo) {
    std::map<Coord3, std::array<const HostVoxel*, 8>> parents;
    for (const auto& [c, v] : below) {
        auto& children = parents.try_emplace({c[0] >> 1, c[1] >> 1, c[2] >> 1}).first->second; // all null
        children[((c[0] & 1) << 2) | ((c[1] & 1) << 1) | (c[2] & 1)] = &v;
    }
    HostLevel level;
    for (const auto& [p, children] : parents) {
        HostVoxel& c = level[p];
        for (const HostVoxel* child : children) {
            if (!child) continue;
            c.densitySum += double(child->density);
            for (int i = 0; i < 6; ++i) c.tensor[i] += child->tensor[i];
            if (albedo)
                for (int k = 0; k < 3; ++k) c.colourSum[k] += double(child->density) * child->albedo[k];
        }
    }
    resolve(level, 8.0, albedo);
    return level;
}

/// Level-0 sums straight over each coarse voxel's box, unrounded: what the
/// levels approximate.
struct ExactVoxel {
    double densitySum = 0.0, tensor[6] = {0, 0, 0, 0, 0, 0}, colourSum[3] = {0, 0, 0};
};
std::map<Coord3, ExactVoxel> exactLevel(const BrickVolume& volume, int level, bool albedo) {
    std::map<Coord3, ExactVoxel> out;
    for (const VoxelBrick& b : volume.bricks) {
        const glm::ivec3 o = brickCoord(b.key) * kBrickSize;
        for (int v = 0; v < kBrickVoxels; ++v) {
            if (!b.isActive(v)) continue;
            const glm::ivec3 p = o + glm::ivec3(v >> 6, (v >> 3) & 7, v & 7);
            ExactVoxel& c = out[{p.x >> level, p.y >> level, p.z >> level}];
            const double d = b.density[v];
            const glm::dvec3 a(b.orientation[v]);
            c.densitySum += d;
            const double t[6] = {a.x * a.x, a.y * a.y, a.z * a.z, a.x * a.y, a.x * a.z, a.y * a.z};
            for (int i = 0; i < 6; ++i) c.tensor[i] += d * t[i];
            if (albedo)
                for (int k = 0; k < 3; ++k) c.colourSum[k] += d * b.albedo[v][k];
        }
    }
    return out;
}

/// The gap between a symmetric 3x3 matrix's largest eigenvalue and its
/// Rayleigh quotient at `a`, relative: 0 when `a` is its principal axis.
double axisGap(const double t[6], glm::dvec3 a) {
    const auto rayleigh = [&](glm::dvec3 x) {
        x = glm::normalize(x);
        return t[0] * x.x * x.x + t[1] * x.y * x.y + t[2] * x.z * x.z +
               2.0 * (t[3] * x.x * x.y + t[4] * x.x * x.z + t[5] * x.y * x.z);
    };
    const double lambda = rayleigh(principalAxis(t));
    return (lambda - rayleigh(a)) / lambda;
}

template <typename GridT> typename GridT::Ptr readGrid(const fs::path& path, const std::string& name) {
    openvdb::io::File file(path.string());
    file.open();
    const openvdb::GridBase::Ptr g = file.hasGrid(name) ? file.readGrid(name) : nullptr;
    file.close();
    return openvdb::gridPtrCast<GridT>(g);
}

VolumeMetadata someMetadata() {
    VolumeMetadata meta;
    meta.input = "preview test volume";
    meta.backend = "cpu";
    return meta;
}

/// Writes `volume` with levels first..last, in batches that cut through
/// clusters, from several threads.
void writeInBatches(const fs::path& out, const BrickVolume& volume, int first, int last, bool albedo) {
    VdbWriteOptions options;
    options.lodFirstLevel = first;
    options.lodLevels = last;
    options.albedo = albedo;
    VdbAssembler assembler(out.string(), volume.grid, volume.reduce, options);
    const std::span<const VoxelBrick> all(volume.bricks);
    const std::size_t cuts[] = {0, 7, 40, 41, 130, all.size()};
    std::vector<std::thread> threads;
    for (int i = 4; i >= 0; --i)
        threads.emplace_back([&, i] { assembler.add(all.subspan(cuts[i], cuts[i + 1] - cuts[i]), "batch"); });
    for (std::thread& t : threads) t.join();
    assembler.write(someMetadata());
}

/// Level `number` of the file against `host` voxel for voxel, and against
/// the exact level-0 sums: density, axis, colour, fibre volume.
void checkLevel(const fs::path& out, const BrickVolume& volume, int number, const HostLevel& host, bool albedo) {
    const std::string suffix = "_lod" + std::to_string(number);
    const auto density = readGrid<openvdb::FloatGrid>(out, "density" + suffix);
    const auto orientation = readGrid<openvdb::Vec3SGrid>(out, "orientation" + suffix);
    REQUIRE(density);
    REQUIRE(orientation);
    CHECK(density->voxelSize()[0] == Approx(volume.grid.voxelSize * (1 << number)).epsilon(1e-12));
    CHECK(density->activeVoxelCount() == host.size());
    CHECK(orientation->tree().hasSameTopology(density->tree()));
    const auto colour = albedo ? readGrid<openvdb::Vec3SGrid>(out, "albedo" + suffix) : nullptr;
    CHECK(bool(colour) == albedo);
    const auto exact = exactLevel(volume, number, albedo);
    const auto d = density->getConstAccessor();
    const auto o = orientation->getConstAccessor();
    const auto rgb = (colour ? colour : openvdb::Vec3SGrid::create())->getConstAccessor();
    std::size_t differ = 0, inexact = 0;
    double mass = 0.0;
    for (const auto& [c, want] : host) {
        const openvdb::Coord xyz(c[0], c[1], c[2]);
        const openvdb::Vec3s a = o.getValue(xyz);
        differ += !d.isValueOn(xyz) || d.getValue(xyz) != want.density || a != openvdb::Vec3s(want.axis.x, want.axis.y, want.axis.z);
        if (albedo) differ += rgb.getValue(xyz) != openvdb::Vec3s(want.albedo.x, want.albedo.y, want.albedo.z);
        mass += want.density;
        // Against level 0 unrounded: the mean (one float rounding a level
        // from the first), the principal axis, the mass-weighted colour.
        const ExactVoxel& e = exact.at(c);
        const double mean = e.densitySum / std::pow(8.0, number);
        inexact += std::abs(want.density - mean) / mean > 6e-7;
        inexact += axisGap(e.tensor, glm::dvec3(want.axis)) > 1e-5 || canonicalAxis(glm::dvec3(want.axis)) != glm::dvec3(want.axis);
        for (int k = 0; k < 3 && albedo; ++k) inexact += std::abs(want.albedo[k] - e.colourSum[k] / e.densitySum) > 1e-5;
    }
    CHECK(differ == 0);
    CHECK(inexact == 0);
    const double hl = volume.grid.voxelSize * (1 << number);
    CHECK(std::abs(mass * hl * hl * hl - volume.totalMass()) / volume.totalMass() < 1e-6);
}

} // namespace

TEST_CASE("LOD preview: each level is the host's reduction of level 0, voxel for voxel", "[vdb][lod]") {
    openvdb::initialize();
    for (const bool albedo : {false, true})
        for (const int first : {3, 2}) {
            INFO("albedo " << albedo << ", first level " << first);
            const BrickVolume volume = previewVolume(17, albedo);
            REQUIRE(volume.bricks.size() > 150);
            const int last = maxLodLevels(volume.grid);
            REQUIRE(last == 7);
            const fs::path out = scratch("preview.vdb");
            writeInBatches(out, volume, first, last, albedo);
            HostLevel host = firstLevelFromBricks(volume, first, albedo);
            for (int number = first; number <= last; ++number) {
                INFO("level " << number);
                checkLevel(out, volume, number, host, albedo);
                host = nextLevel(host, albedo);
            }
            for (int number = 1; number < first; ++number)
                CHECK_FALSE(readGrid<openvdb::FloatGrid>(out, "density_lod" + std::to_string(number)));
            fs::remove(out);
        }
}

TEST_CASE("LOD preview: the file's bytes do not depend on batches, threads or brick order", "[vdb][lod]") {
    openvdb::initialize();
    const BrickVolume volume = previewVolume(5, true);
    VdbWriteOptions options;
    options.lodFirstLevel = kPreviewFirstLevel;
    options.lodLevels = maxLodLevels(volume.grid);
    options.albedo = true;
    const fs::path whole = scratch("whole.vdb"), batches = scratch("batches.vdb");
    writeVdb(whole.string(), volume, someMetadata(), options);
    {
        VdbAssembler assembler(batches.string(), volume.grid, volume.reduce, options);
        std::vector<VoxelBrick> shuffled = volume.bricks;
        std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(3));
        for (std::size_t i = 0; i < shuffled.size(); i += 9)
            assembler.add(std::span(shuffled).subspan(i, std::min<std::size_t>(9, shuffled.size() - i)), "batch");
        assembler.write(someMetadata());
    }
    const bool sameBytes = test::vdbBytesWithoutUuid(whole) == test::vdbBytesWithoutUuid(batches);
    CHECK(sameBytes);
    fs::remove(whole);
    fs::remove(batches);
}

TEST_CASE("LOD preview: the file says its first level, each grid its level and voxel size", "[vdb][lod][metadata]") {
    openvdb::initialize();
    const BrickVolume volume = previewVolume(2, true);
    VdbWriteOptions options;
    options.lodFirstLevel = 3;
    options.lodLevels = 5;
    options.albedo = true;
    const fs::path out = scratch("metadata.vdb");
    writeVdb(out.string(), volume, someMetadata(), options);
    openvdb::io::File file(out.string());
    file.open();
    CHECK(file.getMetadata()->metaValue<std::int32_t>("lod_levels") == 5);
    CHECK(file.getMetadata()->metaValue<std::int32_t>("lod_first_level") == 3);
    // By name (getGrids sorts them; test_vdb_stream_writer.cpp shows the
    // file's order is OpenVDB's for the same list: level by level).
    const openvdb::GridPtrVecPtr grids = file.getGrids();
    file.close();
    const std::map<std::string, int> levels{{"albedo", 0},           {"albedo_lod3", 3},      {"albedo_lod4", 4},
                                            {"albedo_lod5", 5},      {"density", 0},          {"density_lod3", 3},
                                            {"density_lod4", 4},     {"density_lod5", 5},     {"orientation", 0},
                                            {"orientation_lod3", 3}, {"orientation_lod4", 4}, {"orientation_lod5", 5}};
    REQUIRE(grids->size() == levels.size());
    auto want = levels.begin();
    for (const openvdb::GridBase::Ptr& grid : *grids) {
        const openvdb::GridBase& g = *grid;
        const auto [name, level] = *want++;
        INFO(name);
        CHECK(g.getName() == name);
        if (level > 0)
            CHECK(g.metaValue<std::int32_t>("lod_level") == level);
        else
            CHECK_FALSE(g.getMetadata<openvdb::Int32Metadata>("lod_level"));
        const openvdb::Vec3d c = g.transform().indexToWorld(openvdb::Coord(3, 1, 2));
        const double hl = volume.grid.voxelSize * (1 << level);
        CHECK(c.x() == Approx(volume.grid.origin.x + 3.5 * hl).epsilon(1e-12));
        CHECK(c.z() == Approx(volume.grid.origin.z + 2.5 * hl).epsilon(1e-12));
    }
    fs::remove(out);
}

TEST_CASE("LOD preview: --lod's words, and the levels each gives on a grid", "[vdb][lod]") {
    CHECK(parseLodRequest("preview") == LodRequest{});
    CHECK(parseLodRequest("0") == LodRequest::none());
    CHECK(parseLodRequest("4") == LodRequest::full(4));
    for (const char* bad : {"", "-1", "21", "2.5", " 3", "full", "1e1"}) {
        INFO(bad);
        CHECK_THROWS_AS(parseLodRequest(bad), Error);
    }
    CHECK(toString(LodRequest{}) == "preview");
    CHECK(toString(LodRequest::full(4)) == "4");
    VoxelGrid grid;
    grid.dims = {1024, 300, 20};
    CHECK(lodLevelsFor(LodRequest{}, grid).first == 3);
    CHECK(lodLevelsFor(LodRequest{}, grid).last == 7);
    CHECK(lodLevelsFor(LodRequest::none(), grid).last == 0);
    CHECK(lodLevelsFor(LodRequest::full(2), grid).first == 1);
    CHECK(lodLevelsFor(LodRequest::full(2), grid).last == 2);
    CHECK_THROWS_AS(lodLevelsFor(LodRequest::full(8), grid), Error);
    // Too small for level 3: no preview, and no error (it is the default).
    grid.dims = {63, 40, 40};
    CHECK(lodLevelsFor(LodRequest{}, grid).last == 0);
    grid.dims = {64, 40, 40};
    CHECK(lodLevelsFor(LodRequest{}, grid).first == 3);
    CHECK(lodLevelsFor(LodRequest{}, grid).last == 3);
}

namespace {

struct FileGrids {
    std::vector<std::string> names; ///< by name
    std::int32_t lodLevels = 0, lodFirstLevel = 0; ///< 0: no such item
};

FileGrids fileGrids(const fs::path& path) {
    openvdb::io::File file(path.string());
    file.open();
    FileGrids out;
    const openvdb::GridPtrVecPtr grids = file.getGrids();
    for (const openvdb::GridBase::Ptr& g : *grids) out.names.push_back(g->getName());
    const openvdb::MetaMap::Ptr meta = file.getMetadata();
    if (const auto m = meta->getMetadata<openvdb::Int32Metadata>("lod_levels")) out.lodLevels = m->value();
    if (const auto m = meta->getMetadata<openvdb::Int32Metadata>("lod_first_level")) out.lodFirstLevel = m->value();
    file.close();
    return out;
}

double gridMass(const openvdb::FloatGrid& g) {
    double sum = 0.0;
    for (auto it = g.cbeginValueOn(); it; ++it) sum += *it;
    const double h = g.voxelSize()[0];
    return sum * h * h * h;
}

} // namespace

TEST_CASE("CLI: voxelize and merge write the preview pyramid by default, none with --lod 0, every level with --lod N", "[cli][lod]") {
    openvdb::initialize();
    const fs::path bcc = scratch("knit.bcc"), work = scratch("knit.work");
    fs::remove_all(work);
    REQUIRE(test::runYarnvox("gen --pattern knit --crossings 40 --shape cylinder --seed 2 -o " + bcc.string()).exitCode == 0);
    const auto voxelize = [&](const fs::path& out, const std::string& more) {
        fs::remove(out);
        const test::RunResult r = test::runYarnvox("voxelize " + bcc.string() + " -o " + out.string() +
                                                   " --backend cpu --resolution 128 --quiet " + more);
        INFO(r.output);
        REQUIRE(r.exitCode == 0);
    };
    // The grid is 144 voxels on its longest axis: levels 1 to 4, the preview 3 and 4.
    const fs::path preview = scratch("preview.vdb"), none = scratch("none.vdb"), full = scratch("full.vdb");
    voxelize(preview, "--work-dir " + work.string() + " --keep-work-dir");
    voxelize(none, "--lod 0");
    voxelize(full, "--lod 2");
    const FileGrids p = fileGrids(preview);
    CHECK(p.names == std::vector<std::string>{"density", "density_lod3", "density_lod4", "orientation",
                                              "orientation_lod3", "orientation_lod4"});
    CHECK(p.lodLevels == 4);
    CHECK(p.lodFirstLevel == 3);
    const FileGrids n = fileGrids(none);
    CHECK(n.names == std::vector<std::string>{"density", "orientation"});
    CHECK(n.lodLevels == 0);
    CHECK(n.lodFirstLevel == 0);
    const FileGrids f = fileGrids(full);
    CHECK(f.names == std::vector<std::string>{"density", "density_lod1", "density_lod2", "orientation",
                                              "orientation_lod1", "orientation_lod2"});
    CHECK(f.lodLevels == 2);
    CHECK(f.lodFirstLevel == 0); // files with every level keep the items they had

    // Level 0 is the same with or without the pyramid, and each level keeps its fibre volume.
    const auto d0 = readGrid<openvdb::FloatGrid>(preview, "density");
    const auto plain = readGrid<openvdb::FloatGrid>(none, "density");
    CHECK(d0->tree().hasSameTopology(plain->tree()));
    std::size_t differ = 0;
    const auto acc = plain->getConstAccessor();
    for (auto it = d0->cbeginValueOn(); it; ++it) differ += acc.getValue(it.getCoord()) != *it;
    CHECK(differ == 0);
    // The default stores halves, each within 2^-11 relative of its float (the
    // levels are made from the floats): the masses agree within twice that.
    for (const char* level : {"density_lod3", "density_lod4"}) {
        INFO(level);
        const auto d = readGrid<openvdb::FloatGrid>(preview, level);
        CHECK(std::abs(gridMass(*d) - gridMass(*d0)) / gridMass(*d0) < std::ldexp(1.0, -10));
    }

    // merge takes the same default, and the same words.
    const fs::path merged = scratch("merged.vdb"), mergedNone = scratch("merged-none.vdb");
    for (const auto& [out, more] : {std::pair(merged, std::string()), std::pair(mergedNone, std::string(" --lod 0"))}) {
        fs::remove(out);
        const test::RunResult r = test::runYarnvox("merge " + work.string() + " -o " + out.string() + " --quiet" + more);
        INFO(r.output);
        REQUIRE(r.exitCode == 0);
    }
    CHECK(test::vdbBytesWithoutUuid(merged) == test::vdbBytesWithoutUuid(preview));
    CHECK(test::vdbBytesWithoutUuid(mergedNone) == test::vdbBytesWithoutUuid(none));

    // A grid under 64 voxels has no level 3: no preview, and no error.
    const fs::path small = scratch("small.vdb");
    fs::remove(small);
    const test::RunResult r = test::runYarnvox("voxelize " + bcc.string() + " -o " + small.string() +
                                               " --backend cpu --resolution 40 --quiet");
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    CHECK(fileGrids(small).names == std::vector<std::string>{"density", "orientation"});
    CHECK(fileGrids(small).lodLevels == 0);

    // A word --lod does not take is refused before any work, naming the words it takes.
    const fs::path refused = scratch("refused.vdb");
    fs::remove(refused);
    const test::RunResult bad = test::runYarnvox("voxelize " + bcc.string() + " -o " + refused.string() +
                                                 " --backend cpu --resolution 64 --lod full");
    CHECK(bad.exitCode != 0);
    CHECK(bad.output.find("'full' is not preview") != std::string::npos);
    CHECK_FALSE(fs::exists(refused));
    fs::remove_all(work);
}

TEST_CASE("CLI: the dense method writes no preview pyramid, and --lod N as before", "[gl][cli][lod]") {
    YV_REQUIRE_GL();
    openvdb::initialize();
    const fs::path bcc = scratch("plain.bcc"), dense = scratch("dense.vdb"), denseLod = scratch("dense-lod.vdb");
    REQUIRE(test::runYarnvox("gen --pattern plain --crossings 16 -o " + bcc.string()).exitCode == 0);
    for (const auto& [out, more] : {std::pair(dense, std::string()), std::pair(denseLod, std::string(" --lod 1"))}) {
        fs::remove(out);
        const test::RunResult r = test::runYarnvox("voxelize " + bcc.string() + " -o " + out.string() +
                                                   " --method dense --resolution 96 --quiet" + more);
        INFO(r.output);
        REQUIRE(r.exitCode == 0);
    }
    CHECK(fileGrids(dense).names == std::vector<std::string>{"density", "orientation"});
    CHECK(fileGrids(denseLod).names ==
          std::vector<std::string>{"density", "density_lod1", "orientation", "orientation_lod1"});
}

// What a .vdb stores without --precision: halves (OpenVDB's saveFloatAsHalf),
// each the float run's value rounded, for voxelize and merge; a .vol output
// keeps the float values unless --precision asks otherwise.
#include "run_cli.h"
#include "test_helpers.h"
#include "vdb_bytes.h"

#include <catch2/catch.hpp>

#include <openvdb/math/Half.h>
#include <openvdb/openvdb.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace fs = std::filesystem;
using yv::test::runYarnvox;

namespace {

fs::path scratch(const std::string& name) { return yv::test::processScratchDir("yv_default_precision_test") / name; }

/// A small knit made once; voxelize's options shared by the runs compared.
const fs::path& knit() {
    static const fs::path bcc = [] {
        const fs::path p = scratch("knit.bcc");
        const auto gen = runYarnvox("gen --pattern knit --shape cylinder --crossings 60 --seed 4 -o " + p.string());
        INFO(gen.output);
        REQUIRE(gen.exitCode == 0);
        return p;
    }();
    return bcc;
}
const std::string kVoxelize = " --backend cpu --resolution 72 --twist 2 --quiet";

void voxelize(const fs::path& out, const std::string& more) {
    const auto r = runYarnvox("voxelize " + knit().string() + " -o " + out.string() + kVoxelize + more);
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
}

openvdb::GridPtrVecPtr readGrids(const fs::path& vdb) {
    openvdb::initialize();
    openvdb::io::File file(vdb.string());
    file.open();
    openvdb::GridPtrVecPtr grids = file.getGrids();
    file.close();
    return grids;
}

openvdb::GridBase::Ptr named(const openvdb::GridPtrVecPtr& grids, const std::string& name) {
    for (const auto& g : *grids)
        if (g->getName() == name) return g;
    FAIL("no grid " << name);
    return {};
}

float rounded(float v) { return float(openvdb::math::half(v)); }
openvdb::Vec3s rounded(const openvdb::Vec3s& v) { return {rounded(v[0]), rounded(v[1]), rounded(v[2])}; }

/// Every active voxel of `halves` is the one of `floats` rounded to a half,
/// the same voxels are active in both, and at least one value is not a half
/// already (so a float file would fail). Returns the voxels compared.
template <class GridT>
openvdb::Index64 checkRounded(const openvdb::GridBase::Ptr& floatsBase, const openvdb::GridBase::Ptr& halvesBase) {
    const auto floats = openvdb::gridPtrCast<GridT>(floatsBase);
    const auto halves = openvdb::gridPtrCast<GridT>(halvesBase);
    REQUIRE(floats);
    REQUIRE(halves);
    CHECK_FALSE(floats->saveFloatAsHalf());
    CHECK(halves->saveFloatAsHalf());
    REQUIRE(halves->activeVoxelCount() == floats->activeVoxelCount());
    const auto halfValues = halves->getConstAccessor();
    openvdb::Index64 changed = 0, compared = 0;
    for (auto it = floats->cbeginValueOn(); it; ++it) {
        const auto want = rounded(*it);
        INFO(floats->getName() << " voxel " << it.getCoord() << ": float " << *it);
        REQUIRE(halfValues.isValueOn(it.getCoord()));
        CHECK(halfValues.getValue(it.getCoord()) == want);
        changed += want != *it ? 1 : 0;
        ++compared;
    }
    CHECK(changed > 0);
    return compared;
}

/// Both files' density and orientation grids, level 0 and the preview's level 3.
void checkHalvesOfFloats(const fs::path& floatFile, const fs::path& halfFile) {
    const auto floats = readGrids(floatFile), halves = readGrids(halfFile);
    REQUIRE(floats->size() == halves->size());
    for (const std::string level : {"", "_lod3"}) {
        CHECK(checkRounded<openvdb::FloatGrid>(named(floats, "density" + level), named(halves, "density" + level)) > 0);
        CHECK(checkRounded<openvdb::Vec3SGrid>(named(floats, "orientation" + level),
                                               named(halves, "orientation" + level)) > 0);
    }
}

std::string fileBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

} // namespace

TEST_CASE("CLI: voxelize without --precision writes halves, the --precision float run's values rounded", "[cli][vdb]") {
    const fs::path byDefault = scratch("default.vdb"), floats = scratch("float.vdb"), halves = scratch("half.vdb");
    const fs::path stats = scratch("default.json");
    voxelize(byDefault, " --stats " + stats.string());
    voxelize(floats, " --precision float");
    voxelize(halves, " --precision half");
    checkHalvesOfFloats(floats, byDefault);
    // The default is --precision half, byte for byte but the file's UUID.
    CHECK(yv::test::vdbBytesWithoutUuid(byDefault) == yv::test::vdbBytesWithoutUuid(halves));
    CHECK(fs::file_size(byDefault) < fs::file_size(floats));
    CHECK(fileBytes(stats).find("\"vdb_precision\": \"half\"") != std::string::npos);
}

TEST_CASE("CLI: merge without --precision writes halves too", "[cli][vdb]") {
    const fs::path work = scratch("merge.work"), floats = scratch("merged-float.vdb"),
                   byDefault = scratch("merged-default.vdb");
    voxelize(scratch("merge-run.vdb"), " --work-dir " + work.string());
    auto r = runYarnvox("merge " + work.string() + " -o " + floats.string() + " --precision float --quiet");
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    r = runYarnvox("merge " + work.string() + " -o " + byDefault.string() + " --quiet");
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    checkHalvesOfFloats(floats, byDefault);
}

TEST_CASE("CLI: a .vol output keeps the float values unless --precision half is given", "[cli][vdb]") {
    voxelize(scratch("default.vol"), "");
    voxelize(scratch("float.vol"), " --precision float");
    voxelize(scratch("half.vol"), " --precision half");
    const std::string byDefault = fileBytes(scratch("default.vol"));
    REQUIRE(byDefault.size() > 48);
    CHECK(byDefault == fileBytes(scratch("float.vol")));
    CHECK(byDefault != fileBytes(scratch("half.vol")));
}

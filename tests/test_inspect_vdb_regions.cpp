// The zoom regions a .vdb records (the density grid's "yarnvox_regions"):
// `yarnvox inspect FILE.vdb` gives the same boxes, framings and outlines as
// the run's work directory, and a .vdb that records none says so.
#include "core/error.h"
#include "gpu/egl_context.h"
#include "inspect/inspect_vdb.h"
#include "inspect/png_image.h"
#include "run_cli.h"
#include "test_helpers.h"
#include "core/run_metadata.h"

#include <catch2/catch.hpp>
#include <openvdb/openvdb.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <tuple>

using namespace yv;
namespace fs = std::filesystem;

namespace {

struct Scratch : test::ScratchDir {
    Scratch() : test::ScratchDir("yv_test_vdb_regions") {}
};

/// A generated knit voxelized on the CPU into a few dozen small zoom regions,
/// kept as a work directory beside its .vdb.
void voxelizeWithWorkDir(const fs::path& scratch) {
    const std::string bcc = (scratch / "knit.bcc").string();
    REQUIRE(test::runYarnvox("gen --pattern knit --crossings 20 --shape cylinder --seed 3 --quiet -o " + bcc).exitCode == 0);
    const test::RunResult v = test::runYarnvox("voxelize " + bcc + " -o " + (scratch / "knit.vdb").string() +
                                               " --backend cpu --resolution 64 --fragment-budget 12000 --quiet --work-dir " +
                                               (scratch / "work").string());
    INFO(v.output);
    REQUIRE(v.exitCode == 0);
}

/// (id, min, max, active voxels) of every row of an `inspect --json` region_table.
using Row = std::tuple<std::uint64_t, std::string, std::string, std::uint64_t>;
std::vector<Row> regionTable(const std::string& json) {
    const std::size_t table = json.find("\"region_table\": [");
    REQUIRE(table != std::string::npos);
    // Each row is one flat object: its fields are looked up between its braces
    // (string scanning: GCC 12 warns inside <regex> under the sanitizer build).
    const auto field = [&](std::size_t from, std::size_t to, const std::string& key) -> std::string {
        const std::string quoted = "\"" + key + "\": ";
        std::size_t at = json.find(quoted, from);
        REQUIRE(at < to);
        at += quoted.size();
        if (json[at] == '"') return json.substr(at + 1, json.find('"', at + 1) - at - 1);
        return json.substr(at, json.find_first_not_of("0123456789", at) - at);
    };
    std::vector<Row> rows;
    for (std::size_t id = json.find("\"id\": ", table); id != std::string::npos; id = json.find("\"id\": ", id + 1)) {
        if (json[json.find_last_not_of(" \n\t", id - 1)] != '{') continue; // a row starts with its id
        const std::size_t close = json.find('}', id);
        rows.emplace_back(std::stoull(field(id, close, "id")), field(id, close, "min"), field(id, close, "max"),
                          std::stoull(field(id, close, "active_voxels")));
    }
    return rows;
}

/// A .vdb with a float "density" grid written by OpenVDB itself; `regions`
/// (when given) as the density grid's yarnvox_regions item.
void writeForeignVdb(const std::string& path, const std::string* regions = nullptr) {
    openvdb::initialize();
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("density");
    auto acc = grid->getAccessor();
    for (int i = 0; i < 20; ++i)
        for (int j = 0; j < 6; ++j) acc.setValue(openvdb::Coord(i, j, 3), 0.8f);
    if (regions) grid->insertMeta(kRegionsMetadataName, openvdb::StringMetadata(*regions));
    openvdb::io::File(path).write({grid});
}

std::size_t differingPixels(const RgbImage& a, const RgbImage& b) {
    REQUIRE(a.width == b.width);
    REQUIRE(a.height == b.height);
    std::size_t n = 0;
    for (std::size_t p = 0; p < a.pixels.size(); p += 3)
        for (std::size_t c = 0; c < 3; ++c)
            if (std::abs(int(a.pixels[p + c]) - int(b.pixels[p + c])) > 2) {
                ++n;
                break;
            }
    return n;
}

} // namespace

TEST_CASE("vdb regions: the record reads back as written and malformed records are refused", "[inspect]") {
    const std::vector<RecordedRegion> regions = {{0, {0, 0, 0}, {64, 64, 32}, 1234}, {7, {-8, 16, 0}, {8, 48, 8}, 0}};
    const std::string text = encodeRegions(regions);
    CHECK(text == encodeRegions(regions));
    const std::vector<RecordedRegion> back = decodeRegions(text, "test");
    REQUIRE(back.size() == regions.size());
    for (std::size_t i = 0; i < back.size(); ++i) {
        CHECK(back[i].id == regions[i].id);
        CHECK(back[i].min == regions[i].min);
        CHECK(back[i].max == regions[i].max);
        CHECK(back[i].activeVoxels == regions[i].activeVoxels);
    }
    CHECK(decodeRegions("", "test").empty());
    for (const char* bad : {"1 0 0 0 8 8", "1 0 0 0 8 8 8 5 9", "1 0 0 0 0 8 8 5", "x 0 0 0 8 8 8 5", "1 0 0 0 8 8 8 5;;"})
        CHECK_THROWS_WITH(decodeRegions(bad, "f.vdb"), Catch::Contains("f.vdb") && Catch::Contains("region entry"));
}

TEST_CASE("vdb regions: a run's .vdb gives the same region boxes and heat as its work directory", "[inspect][cli]") {
    Scratch scratch;
    voxelizeWithWorkDir(scratch.path);
    const test::RunResult work = test::runYarnvox("inspect " + (scratch.path / "work").string() + " --json");
    const test::RunResult vdb = test::runYarnvox("inspect " + (scratch.path / "knit.vdb").string() + " --json");
    INFO(work.output << vdb.output);
    REQUIRE(work.exitCode == 0);
    REQUIRE(vdb.exitCode == 0);
    const std::vector<Row> fromWork = regionTable(work.output), fromVdb = regionTable(vdb.output);
    CHECK(fromWork.size() > 2);
    CHECK(fromVdb == fromWork);
    // The record is on the density grid, not among the file's items a summary lists.
    CHECK(vdb.output.find("\"yarnvox_regions\"") == std::string::npos);

    // `yarnvox merge` of the work directory records the same regions.
    const std::string merged = (scratch.path / "merged.vdb").string();
    const test::RunResult m = test::runYarnvox("merge " + (scratch.path / "work").string() + " -o " + merged);
    INFO(m.output);
    REQUIRE(m.exitCode == 0);
    CHECK(readVdbRegions(merged).size() == fromWork.size());
    const test::RunResult mergedJson = test::runYarnvox("inspect " + merged + " --json");
    REQUIRE(mergedJson.exitCode == 0);
    CHECK(regionTable(mergedJson.output) == fromWork);
}

TEST_CASE("vdb regions: --region on the .vdb frames the box it frames on the work directory", "[inspect][gl][cli]") {
    YV_REQUIRE_GL();
    Scratch scratch;
    voxelizeWithWorkDir(scratch.path);
    const std::string work = (scratch.path / "work").string(), vdb = (scratch.path / "knit.vdb").string();
    // The hottest region: the most to compare.
    const std::vector<RecordedRegion> regions = readVdbRegions(vdb);
    REQUIRE(!regions.empty());
    const RecordedRegion hot = *std::max_element(regions.begin(), regions.end(), [](const auto& a, const auto& b) {
        return a.activeVoxels < b.activeVoxels;
    });
    REQUIRE(hot.activeVoxels > 0);
    const std::string id = std::to_string(hot.id);
    const std::string fromWork = (scratch.path / "work.png").string(), fromVdb = (scratch.path / "vdb.png").string();
    const test::RunResult w = test::runYarnvox("inspect " + work + " --render raycast --region " + id + " --size 80x60 -o " + fromWork);
    const test::RunResult v = test::runYarnvox("inspect " + vdb + " --render raycast --region " + id + " --size 80x60 -o " + fromVdb);
    INFO(w.output << v.output);
    REQUIRE(w.exitCode == 0);
    REQUIRE(v.exitCode == 0);
    const RgbImage a = readPng(fromWork), b = readPng(fromVdb);
    CHECK(differingPixels(a, b) <= std::size_t(a.width * a.height / 100));
    // Framed, not the whole volume: the region fills more of the picture.
    const std::string whole = (scratch.path / "whole.png").string();
    REQUIRE(test::runYarnvox("inspect " + vdb + " --render raycast --size 80x60 -o " + whole).exitCode == 0);
    CHECK(differingPixels(b, readPng(whole)) > std::size_t(a.width * a.height / 20));

    // An id the file does not record: one line, no picture.
    const std::string none = (scratch.path / "none.png").string();
    const test::RunResult bad = test::runYarnvox("inspect " + vdb + " --render raycast --region 99999 -o " + none);
    INFO(bad.output);
    CHECK(bad.exitCode != 0);
    CHECK(bad.output.find("has no region 99999") != std::string::npos);
    CHECK(!fs::exists(none));
}

TEST_CASE("vdb regions: --regions draws the recorded outlines over a render of the .vdb", "[inspect][gl][cli]") {
    YV_REQUIRE_GL();
    Scratch scratch;
    voxelizeWithWorkDir(scratch.path);
    const std::string work = (scratch.path / "work").string(), vdb = (scratch.path / "knit.vdb").string();
    const std::string plain = (scratch.path / "plain.png").string(), outlined = (scratch.path / "outlined.png").string();
    const std::string fromWork = (scratch.path / "work.png").string();
    REQUIRE(test::runYarnvox("inspect " + vdb + " --render mip --size 96x72 -o " + plain).exitCode == 0);
    const test::RunResult r = test::runYarnvox("inspect " + vdb + " --render mip --regions --size 96x72 --json -o " + outlined);
    const test::RunResult w = test::runYarnvox("inspect " + work + " --render mip --regions --size 96x72 --json -o " + fromWork);
    INFO(r.output << w.output);
    REQUIRE(r.exitCode == 0);
    REQUIRE(w.exitCode == 0);
    const std::string heat = "\"regions\": " + std::to_string(readVdbRegions(vdb).size());
    CHECK(r.output.find("\"region_heat\"") != std::string::npos);
    CHECK(r.output.find(heat) != std::string::npos);
    const RgbImage a = readPng(plain), b = readPng(outlined), c = readPng(fromWork);
    CHECK(differingPixels(a, b) > std::size_t(a.width * a.height / 50));
    CHECK(differingPixels(b, c) <= std::size_t(a.width * a.height / 100));
}

TEST_CASE("vdb regions: a .vdb that records no regions says so in one line", "[inspect][gl][cli]") {
    YV_REQUIRE_GL();
    Scratch scratch;
    const std::string foreign = (scratch.path / "foreign.vdb").string();
    writeForeignVdb(foreign);
    CHECK(readVdbRegions(foreign).empty());
    const std::string png = (scratch.path / "out.png").string();
    for (const char* args : {" --render mip --regions -o ", " --render raycast --region 0 -o "}) {
        const test::RunResult r = test::runYarnvox("inspect " + foreign + args + png);
        INFO(args << ": " << r.output);
        CHECK(r.exitCode != 0);
        CHECK(r.output.find("records no zoom regions") != std::string::npos);
        CHECK(std::count(r.output.begin(), r.output.end(), '\n') <= 2);
        CHECK(!fs::exists(png));
    }
    const test::RunResult summary = test::runYarnvox("inspect " + foreign);
    INFO(summary.output);
    CHECK(summary.exitCode == 0);
    CHECK(summary.output.find("zoom regions: none recorded") != std::string::npos);

    // A malformed record is named, not taken for no regions.
    const std::string broken = (scratch.path / "broken.vdb").string();
    const std::string text = "0 0 0 0 8 8";
    writeForeignVdb(broken, &text);
    const test::RunResult b = test::runYarnvox("inspect " + broken + " --render mip --regions -o " + png);
    INFO(b.output);
    CHECK(b.exitCode != 0);
    CHECK(b.output.find("yarnvox_regions") != std::string::npos);
    CHECK(!fs::exists(png));
}

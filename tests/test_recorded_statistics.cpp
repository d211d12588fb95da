// The voxel statistics a yarnvox .vdb records when it is written (file
// metadata "yarnvox_statistics", core/voxel_statistics.h): equal, bit for
// bit, to a count of every voxel the file holds, whatever order and threads
// the bricks came in; used by `inspect FILE.vdb` so that no voxel is read;
// checked by `inspect --verify`, which names a record that no longer
// matches the voxels; refused in one line when malformed.
#include "core/voxel_statistics.h"
#include "inspect/inspect_vdb.h"
#include "run_cli.h"
#include "test_helpers.h"
#include "vdb/file_metadata.h"
#include "vdb/vdb_writer.h"
#include "vdb_bytes.h"

#include <catch2/catch.hpp>
#include <openvdb/openvdb.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

using namespace yv;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

struct Scratch : test::ScratchDir {
    Scratch() : test::ScratchDir("yv_test_recorded_statistics") {}
};

/// Bricks of random densities (some above 1, some tiny) and axes (most of
/// unit length, some not), dense and sparse, over a wide grid.
BrickVolume randomVolume() {
    BrickVolume v;
    v.grid.voxelSize = 0.05;
    v.grid.dims = glm::ivec3(2048, 256, 1024);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (int i = 0; i < 300; ++i) {
        VoxelBrick b;
        b.key = brickKey(glm::ivec3(i % 17 * 7, i % 5, i / 17 * 3));
        for (int vox = 0; vox < kBrickVoxels; ++vox) {
            if (i % 4 == 1 && vox % 29 != 0) continue;
            b.activeMask[vox >> 6] |= std::uint64_t(1) << (vox & 63);
            const float u = unit(rng);
            b.density[vox] = u < 0.05f ? 1e-6f * u : u < 0.1f ? 1.0f + u : u;
            const glm::vec3 a(unit(rng) - 0.5f, unit(rng) - 0.5f, unit(rng) + 0.1f);
            b.orientation[vox] = vox % 13 == 0 ? a : glm::normalize(a);
        }
        v.bricks.push_back(b);
    }
    std::sort(v.bricks.begin(), v.bricks.end(), [](const VoxelBrick& a, const VoxelBrick& b) { return a.key < b.key; });
    return v;
}

/// `volume` written by the streaming writer, its bricks handed over in
/// batches of `batch` in a shuffled order, from several threads at once.
void writeShuffled(const std::string& path, const BrickVolume& volume, VdbPrecision precision, std::size_t batch,
                   unsigned seed) {
    std::vector<VoxelBrick> bricks = volume.bricks;
    std::shuffle(bricks.begin(), bricks.end(), std::mt19937(seed));
    VdbWriteOptions options;
    options.precision = precision;
    VdbAssembler assembler(path, volume.grid, volume.reduce, options);
    const std::size_t batches = (bricks.size() + batch - 1) / batch;
    tbb::parallel_for(std::size_t(0), batches, [&](std::size_t i) {
        const std::size_t first = i * batch, count = std::min(batch, bricks.size() - first);
        assembler.add(std::span<const VoxelBrick>(bricks.data() + first, count));
    });
    assembler.write(VolumeMetadata{});
}

std::string readText(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void writeText(const fs::path& p, const std::string& s) {
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out << s;
}

/// The record's text as the file holds it (through OpenVDB, as any metadata).
std::string recordOf(const std::string& path) {
    openvdb::initialize();
    openvdb::io::File file(path);
    file.open(false);
    const auto item = file.getMetadata()->getMetadata<openvdb::StringMetadata>(kVoxelStatisticsName);
    file.close();
    return item ? item->value() : "";
}

} // namespace

TEST_CASE("Recorded statistics: the record equals a count of every voxel, bit for bit, in any order", "[vdb][inspect]") {
    openvdb::initialize();
    Scratch scratch;
    const BrickVolume volume = randomVolume();
    const VdbPrecision precision = GENERATE(VdbPrecision::Float, VdbPrecision::Half);
    INFO("precision " << toString(precision));
    const std::string a = (scratch.path / "a.vdb").string(), b = (scratch.path / "b.vdb").string();
    writeShuffled(a, volume, precision, 300, 1);
    writeShuffled(b, volume, precision, 7, 2);
    CHECK(test::vdbBytesWithoutUuid(a) == test::vdbBytesWithoutUuid(b));

    const VdbSummary recorded = inspectVdb(a);
    CHECK(recorded.statisticsRecorded);
    const VdbSummary counted = inspectVdb(a, VoxelCount::EveryVoxel);
    CHECK_FALSE(counted.statisticsRecorded);
    CHECK(counted.statisticsChecked);
    CHECK(recorded.voxels == counted.voxels);
    REQUIRE(recorded.grids.size() == 2);
    CHECK(recorded.grids[0].leaves == volume.bricks.size());
    CHECK(recorded.grids[0].leaves == counted.grids[0].leaves);
    CHECK(recorded.grids[0].activeVoxels == counted.grids[0].activeVoxels);
    CHECK(recorded.hasOrientation == counted.hasOrientation);

    // The values as stored: in half precision the record counts the halves, not the floats given.
    VoxelStatistics given;
    for (const VoxelBrick& brick : volume.bricks)
        given.addBrick(brick.density.data(), brick.orientation.data(), brick.activeMask.data());
    CHECK(recorded.voxels.activeVoxels == given.activeVoxels);
    if (precision == VdbPrecision::Float) CHECK(recorded.voxels == given);
    else CHECK(recorded.voxels.densitySum() == Approx(given.densitySum()).epsilon(1e-3));
    CHECK(recorded.voxels.aboveOne > 0);
    CHECK(recorded.voxels.unitAxes < recorded.voxels.activeVoxels);
}

TEST_CASE("Recorded statistics: the record's text reads back exactly, and malformed text is refused", "[vdb][inspect]") {
    const BrickVolume volume = randomVolume();
    VoxelStatistics s;
    for (const VoxelBrick& b : volume.bricks) s.addBrick(b.density.data(), b.orientation.data(), b.activeMask.data());
    const std::string text = statisticsRecord(s, 300);
    std::string why;
    const auto back = parseStatisticsRecord(text, why);
    REQUIRE(back);
    CHECK(back->voxels == s);
    CHECK(back->leaves == 300);
    CHECK(statisticsRecord(back->voxels, back->leaves) == text);

    const auto replaced = [&](const std::string& from, const std::string& to) {
        std::string t = text;
        const std::size_t at = t.find(from);
        REQUIRE(at != std::string::npos);
        return t.replace(at, from.size(), to);
    };
    const std::string bad[] = {
        "",
        text.substr(0, text.size() / 2),
        replaced("version=1", "version=2"),
        replaced("version=1", "version=1 version=1"),
        replaced("leaves=300", "leaves=-3"),
        replaced("leaves=300", "leaves=3x0"),
        replaced("leaves=300", "leaf=300"),
        replaced("active_voxels=", "active_voxels=1"), // no longer the histogram's sum
        replaced("histogram=", "histogram=1,"),
        replaced("density_sum=", "density_sum=x"),
        replaced("axis_sums=", "axis_sums=0:0x0p+0,"),
        text + " extra=1",
    };
    for (const std::string& t : bad) {
        INFO(t);
        why.clear();
        CHECK_FALSE(parseStatisticsRecord(t, why));
        CHECK_FALSE(why.empty());
    }
}

TEST_CASE("Recorded statistics: inspect reads no voxel for them, --verify counts and names a record that changed",
          "[vdb][inspect][cli]") {
    Scratch scratch;
    const fs::path bcc = scratch.path / "g.bcc", vdb = scratch.path / "g.vdb";
    REQUIRE(test::runYarnvox("gen --pattern knit --shape cylinder --crossings 80 --quiet -o " + bcc.string()).exitCode == 0);
    REQUIRE(test::runYarnvox("voxelize " + bcc.string() + " -o " + vdb.string() +
                             " --backend cpu --resolution 80 --yarn-radius 0.12 --quiet")
                .exitCode == 0);
    const auto summary = test::runYarnvox("inspect " + vdb.string());
    REQUIRE(summary.exitCode == 0);
    CHECK_THAT(summary.output, Contains("statistics: recorded in the file when it was written"));
    const auto verified = test::runYarnvox("inspect --verify " + vdb.string());
    INFO(verified.output);
    REQUIRE(verified.exitCode == 0);
    CHECK_THAT(verified.output, Contains("statistics: counted from every voxel, equal to those recorded"));
    // Both print the same numbers: everything before the line that says where they came from.
    const auto numbers = [](const std::string& out) { return out.substr(0, out.find("statistics: ")); };
    CHECK(numbers(summary.output) == numbers(verified.output));

    // A count in the record changed (its grids' bytes, and so their checksums, as
    // they were): the summary trusts the record; --verify counts and says so.
    const std::string record = recordOf(vdb.string());
    REQUIRE_FALSE(record.empty());
    std::string bytes = readText(vdb);
    const std::size_t at = bytes.find(record);
    REQUIRE(at != std::string::npos);
    std::string changed = record;
    const std::size_t above = changed.find("above_one=");
    REQUIRE(above != std::string::npos);
    changed[above + 10] = changed[above + 10] == '9' ? '8' : char(changed[above + 10] + 1);
    // The same length, so the header stays readable: a changed count, not a cut file.
    std::string wrong = bytes;
    wrong.replace(at, record.size(), changed);
    const fs::path edited = scratch.path / "edited.vdb";
    writeText(edited, wrong);
    CHECK(test::runYarnvox("inspect " + edited.string()).exitCode == 0);
    const auto caught = test::runYarnvox("inspect --verify " + edited.string());
    CHECK(caught.exitCode == 1);
    CHECK_THAT(caught.output, Contains(edited.string() + ": the voxels differ from the statistics recorded when the file was written"));

    // A record that cannot be read: one line naming the file and the item.
    std::string broken = record;
    broken.replace(broken.find("version=1"), 9, "version=9");
    wrong = bytes;
    wrong.replace(at, record.size(), broken);
    const fs::path damaged = scratch.path / "damaged.vdb";
    writeText(damaged, wrong);
    const auto refused = test::runYarnvox("inspect " + damaged.string());
    CHECK(refused.exitCode == 1);
    CHECK_THAT(refused.output, Contains(damaged.string() + ": file metadata yarnvox_statistics is damaged: version 9"));
}

// voxelize --bbox through a work directory: the regions on disk hold only the
// box's voxels, `merge` gives the box run's .vdb, --resume with the same box
// goes on where it stopped, and --resume with another box (or none) is
// refused in one line before anything is written. CPU backend: no GL needed.
#include "bbox_runs.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <string>

namespace fs = std::filesystem;
using namespace yv;
using test::BoxFixture;
using test::TestBox;

namespace {

std::size_t lineCount(const std::string& text) { return std::size_t(std::count(text.begin(), text.end(), '\n')); }

} // namespace

TEST_CASE("Bbox: a box run through a work dir merges and resumes to the same voxels", "[bbox][out-of-core][cli]") {
    const BoxFixture f("cpu");
    const fs::path whole = f.path("whole.vdb"), stats = f.path("whole.json");
    f.voxelize(whole, "--stats " + stats.string());
    const TestBox box = BoxFixture::cuttingBox(BoxFixture::dims(test::readStats(stats)));
    const test::BoxTestVoxels wholeVoxels = test::readActiveVoxels(whole);

    const fs::path work = f.path("work"), part = f.path("box.vdb");
    f.voxelize(part, "--bbox " + box.text() + " --work-dir " + work.string());
    const test::BoxTestVoxels partVoxels = test::readActiveVoxels(part);
    CHECK(test::checkBoxIsWholeRestricted(wholeVoxels, partVoxels, box) > 500);

    // The work dir's manifest and the .vdb's file metadata record the box.
    CHECK(test::readStats(work / "manifest")["run"]["bbox"] == box.text());
    openvdb::io::File file(part.string());
    file.open();
    CHECK(file.getMetadata()->metaValue<std::string>("bbox") == box.text());
    file.close();
    openvdb::io::File wholeFile(whole.string());
    wholeFile.open();
    CHECK((*wholeFile.getMetadata())["bbox"] == nullptr); // a whole run's metadata is what it always was
    wholeFile.close();

    // merge reads the regions on disk: the box's voxels and no others.
    const fs::path merged = f.path("merged.vdb");
    REQUIRE(test::runYarnvox("merge " + work.string() + " -o " + merged.string()).exitCode == 0);
    CHECK(test::readActiveVoxels(merged) == partVoxels);

    // The same box resumes: every region is taken from the work dir.
    const fs::path resumed = f.path("resumed.vdb"), resumedStats = f.path("resumed.json");
    f.voxelize(resumed, "--bbox " + box.text() + " --work-dir " + work.string() + " --resume --stats " +
                            resumedStats.string());
    const nlohmann::json rs = test::readStats(resumedStats);
    CHECK(rs["backend_stats"]["regions_resumed"] == rs["backend_stats"]["zoom_regions"]);
    CHECK(rs["backend_stats"]["regions_computed"] == 0);
    CHECK(test::readActiveVoxels(resumed) == partVoxels);

    // Another box, one voxel off on one face, or none: refused in one line, nothing written.
    TestBox other = box;
    other.max[0] -= 1;
    for (const std::string& asked : {"--bbox " + other.text(), std::string()}) {
        const fs::path out = f.path("refused.vdb");
        const test::RunResult r = test::runYarnvox("voxelize " + f.bcc + " -o " + out.string() + f.options + " " +
                                                   asked + " --work-dir " + work.string() + " --resume");
        INFO(r.output);
        CHECK(r.exitCode == 1);
        CHECK(lineCount(r.output) == 1);
        CHECK_THAT(r.output, Catch::Contains("belongs to a different run") && Catch::Contains("made for box " + box.text()));
        CHECK_THAT(r.output, Catch::Contains(asked.empty() ? "asks for the whole garment" : "asks for box " + other.text()));
        CHECK(!fs::exists(out));
    }
    // The work dir is untouched by the refusals: resuming it still gives the box.
    f.voxelize(resumed, "--bbox " + box.text() + " --work-dir " + work.string() + " --resume");
    CHECK(test::readActiveVoxels(resumed) == partVoxels);
}

// voxelize --bbox and --bbox-world refuse what is not a box of the grid: one
// line naming the option and its value, a non-zero exit, and no output, stats
// file or work dir left behind. CPU backend: no GL needed.
#include "plan/box_request.h"
#include "run_cli.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace yv;

namespace {

std::size_t lineCount(const std::string& text) { return std::size_t(std::count(text.begin(), text.end(), '\n')); }

} // namespace

TEST_CASE("Bbox bad input: each mistake is one line naming the option and value, exit 1, nothing written",
          "[bbox][bad-input][cli]") {
    const test::ScratchDir dir("yv_bbox_bad");
    const std::string bcc = (dir.path / "g.bcc").string();
    REQUIRE(test::runYarnvox("gen --pattern plain --shape flat --crossings 16 --quiet -o " + bcc).exitCode == 0);
    struct Case {
        std::string args;
        std::vector<std::string> says;
    };
    const Case cases[] = {
        {"--resolution 32 --bbox 8,0,0,4,8,8", {"--bbox 8,0,0,4,8,8", "holds nothing along x", "max"}},
        {"--resolution 32 --bbox 0,0,0,8,8,0", {"--bbox 0,0,0,8,8,0", "holds nothing along z"}},
        {"--resolution 32 --bbox-world 0,0,0,1,-1,1", {"--bbox-world 0,0,0,1,-1,1", "holds nothing along y"}},
        {"--resolution 32 --bbox-world 0,0,0,nan,1,1", {"--bbox-world 0,0,0,nan,1,1", "nan", "finite"}},
        {"--resolution 32 --bbox-world 0,0,0,inf,1,1", {"--bbox-world 0,0,0,inf,1,1", "finite"}},
        {"--resolution 32 --bbox-world 0,0,0,1e300,1,1", {"--bbox-world 0,0,0,1e300,1,1", "1e12"}},
        {"--resolution 32 --bbox 0,0,0,8,8", {"--bbox 0,0,0,8,8", "5 numbers", "expected six"}},
        {"--resolution 32 --bbox 0,0,0,8,8,8,8", {"--bbox 0,0,0,8,8,8,8", "more than six"}},
        {"--resolution 32 --bbox 0,0,0,8,x,8", {"--bbox 0,0,0,8,x,8", "'x' is not a number"}},
        {"--resolution 32 --bbox 0,0,0.5,8,8,8", {"--bbox 0,0,0.5,8,8,8", "whole number"}},
        {"--resolution 32 --bbox 1000,1000,1000,2000,2000,2000",
         {"--bbox 1000,1000,1000,2000,2000,2000", "lies outside the garment's grid", "nothing to voxelize"}},
        {"--resolution 32 --bbox-world 500,500,500,600,600,600",
         {"--bbox-world 500,500,500,600,600,600", "lies outside the garment's grid"}},
        {"--resolution 32 --bbox 0,0,0,8,8,8 --bbox-world 0,0,0,1,1,1", {"--bbox", "--bbox-world", "excludes"}},
        {"--bbox 0,0,0,8,8,8", {"--bbox 0,0,0,8,8,8", "not defined yet", "--resolution", "--voxel-size"}},
        {"--resolution 32 --method dense --backend gl --bbox 0,0,0,8,8,8", {"--bbox 0,0,0,8,8,8", "sparse method"}},
    };
    for (const Case& c : cases) {
        const fs::path out = dir.path / "out.vdb", stats = dir.path / "out.json", work = dir.path / "work";
        const std::string backend = c.args.find("--backend") == std::string::npos ? " --backend cpu " : " ";
        const test::RunResult r = test::runYarnvox("voxelize " + bcc + backend + "-o " + out.string() + " --stats " +
                                                   stats.string() + " --work-dir " + work.string() + " " + c.args);
        INFO(c.args << "\n" << r.output);
        // 1 for yarnvox's errors; CLI11's own code for options that exclude each other.
        CHECK(r.exitCode != 0);
        CHECK(lineCount(r.output) == 1);
        for (const std::string& s : c.says) CHECK_THAT(r.output, Catch::Contains(s));
        CHECK_FALSE(fs::exists(out));
        CHECK_FALSE(fs::exists(stats));
        CHECK_FALSE(fs::exists(work));
    }
}

TEST_CASE("Bbox bad input: a box is parsed and placed on the grid as documented", "[bbox][bad-input]") {
    const BoxRequest voxels = parseBoxRequest(false, "1,2,3,9,10,11");
    CHECK(voxels.named() == "--bbox 1,2,3,9,10,11");
    VoxelGrid grid;
    grid.origin = {-1.0, 0.0, 2.0};
    grid.voxelSize = 0.5;
    grid.dims = {16, 16, 8};
    BoxOnGrid placed = placeBox(voxels, grid);
    CHECK(placed.text() == "1,2,3,9,10,8");
    CHECK(placed.clipped);
    // World: every voxel whose cell overlaps the box; a face on a voxel boundary takes no voxel beyond it.
    placed = placeBox(parseBoxRequest(true, "-0.5,0.25,2,1,1.3,3.5"), grid);
    CHECK(placed.text() == "1,0,0,4,3,3");
    CHECK_FALSE(placed.clipped);
    CHECK_THROWS_WITH(placeBox(parseBoxRequest(true, "-9,-9,-9,-2,-2,-2"), grid),
                      Catch::Contains("--bbox-world -9,-9,-9,-2,-2,-2: the box lies outside the garment's grid"));
}

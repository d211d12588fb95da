// Every number that gen, merge, inspect and export take (and voxelize's
// whole numbers) is checked where it is parsed: not finite, not a whole
// number where one is counted, outside its range, or inside it but meaning
// nothing (a box outside the volume). Each is refused in one line naming the
// option and the value, before anything is written. docs/reliability.md
// lists them.
#include "run_cli.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

std::size_t lineCount(const std::string& s) { return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n')); }

/// A small garment, its .vdb and work directory, made once for the test case.
struct Volume {
    yv::test::ScratchDir dir{"yv_option_values"};
    std::string bcc = (dir.path / "g.bcc").string(), vdb = (dir.path / "g.vdb").string(),
                work = (dir.path / "g.work").string();
    Volume() {
        REQUIRE(yv::test::runYarnvox("gen --crossings 40 --quiet -o " + bcc).exitCode == 0);
        REQUIRE(yv::test::runYarnvox("voxelize " + bcc + " -o " + vdb + " --backend cpu --resolution 32 --quiet --work-dir " +
                                     work)
                    .exitCode == 0);
    }
    /// What the commands below would write: none may appear.
    std::vector<fs::path> outputs() const {
        return {dir.path / "out.bcc", dir.path / "out.vdb", dir.path / "out.png", dir.path / "out.ply",
                dir.path / "out.vol", dir.path / "out.sggx.vol", dir.path / "report"};
    }
};

struct Case {
    std::string args, option, value, why;
};

/// Runs each case (`{V}` is the .vdb, `{W}` the work directory, `{B}` the
/// garment, `{O}` the scratch folder) and checks the refusal.
void expectRefused(const Volume& v, const std::vector<Case>& cases) {
    for (const Case& c : cases) {
        std::string args = c.args;
        for (const auto& [key, value] : {std::pair<std::string, std::string>{"{V}", v.vdb}, {"{W}", v.work}, {"{B}", v.bcc},
                                         {"{O}", v.dir.path.string()}})
            for (std::size_t at; (at = args.find(key)) != std::string::npos;) args.replace(at, key.size(), value);
        const yv::test::RunResult r = yv::test::runShell("timeout 120 " + std::string(YV_BINARY_DIR) + "/yarnvox " + args);
        INFO("yarnvox " << args << "\n" << r.output);
        CHECK(r.exitCode != 0);
        CHECK_THAT(r.output, Contains("yarnvox: error: ") && Contains(c.option) && Contains(c.value) && Contains(c.why));
        CHECK(lineCount(r.output) == 1);
        for (const fs::path& out : v.outputs()) CHECK_FALSE(fs::exists(out));
    }
}

} // namespace

TEST_CASE("bad input: gen's and merge's numbers are refused naming the option and the value", "[bad-input][cli]") {
    const Volume v;
    expectRefused(v, {
                         {"gen --crossings 1.5 -o {O}/out.bcc", "--crossings", "'1.5'", "not a whole number"},
                         {"gen --crossings nan -o {O}/out.bcc", "--crossings", "'nan'", "not a whole number"},
                         {"gen --crossings inf -o {O}/out.bcc", "--crossings", "'inf'", "not a whole number"},
                         {"gen --crossings 0 -o {O}/out.bcc", "--crossings", "'0'", "not in [1, 100000000]"},
                         {"gen --crossings -3 -o {O}/out.bcc", "--crossings", "'-3'", "not in [1, 100000000]"},
                         {"gen --crossings 1e3 -o {O}/out.bcc", "--crossings", "'1e3'", "in digits"},
                         {"gen --crossings 12x -o {O}/out.bcc", "--crossings", "'12x'", "not a number"},
                         {"gen --seed -1 -o {O}/out.bcc", "--seed", "'-1'", "not in [0, "}, // was seed 2^64 - 1
                         {"gen --seed 1.5 -o {O}/out.bcc", "--seed", "'1.5'", "not a whole number"},
                         {"gen --seed 18446744073709551616 -o {O}/out.bcc", "--seed", "'18446744073709551616'", "not in"},
                         {"gen --spacing nan -o {O}/out.bcc", "--spacing", "'nan'", "not a finite number"},
                         {"merge {W} -o {O}/out.vdb --lod 1.5", "--lod", "'1.5'", "is not preview"},
                         {"merge {W} -o {O}/out.vdb --lod nan", "--lod", "'nan'", "is not preview"},
                         {"merge {W} -o {O}/out.vdb --lod -1", "--lod", "'-1'", "is not preview"},
                         {"merge {W} -o {O}/out.vdb --lod 21", "--lod", "'21'", "from 1 to 20"},
                         // voxelize's whole numbers, by the same check.
                         {"voxelize {B} -o {O}/out.vdb --resolution 32.5", "--resolution", "'32.5'", "not a whole number"},
                         {"voxelize {B} -o {O}/out.vdb --resolution 32 --lod 1.5", "--lod", "'1.5'", "is not preview"},
                         {"voxelize {B} -o {O}/out.vdb --resolution 32 --supersample 2.5", "--supersample", "'2.5'", "not a whole number"},
                         {"voxelize {B} -o {O}/out.vdb --resolution 32 --slices-per-segment 2.5", "--slices-per-segment", "'2.5'",
                          "not a whole number"},
                         {"voxelize {B} -o {O}/out.vdb --resolution 32 --fragment-budget 1e9", "--fragment-budget", "'1e9'", "in digits"},
                     });
    // The largest seed is a seed, and good values still work.
    const yv::test::RunResult ok =
        yv::test::runYarnvox("gen --crossings 40 --seed 18446744073709551615 --quiet -o " + (v.dir.path / "seed.bcc").string());
    CHECK(ok.exitCode == 0);
    CHECK(yv::test::runYarnvox("merge " + v.work + " --lod 1 -o " + (v.dir.path / "lod.vdb").string()).exitCode == 0);
}

TEST_CASE("bad input: inspect's numbers are refused naming the option and the value", "[bad-input][cli]") {
    const Volume v;
    const std::string render = "inspect {V} --size 40x30 -o {O}/out.png --render ";
    const std::string preview = "inspect {B} --size 40x30 -o {O}/out.png --render volumetric-triangles ";
    expectRefused(v, {
                         {"inspect {W} --limit -1", "--limit", "'-1'", "not in [0, "},
                         {"inspect {W} --limit 1.5", "--limit", "'1.5'", "not a whole number"},
                         {render + "isosurface --iso nan", "--iso", "'nan'", "not a finite number"}, // drew nothing, exit 0
                         {render + "isosurface --iso inf", "--iso", "'inf'", "not a finite number"},
                         {render + "isosurface --iso -inf", "--iso", "'-inf'", "not a finite number"},
                         {render + "isosurface --iso 0", "--iso", "'0'", "not in ["},
                         {render + "raycast --view 1e300,20,4", "--view", "'1e300,20,4'", "azimuth"},
                         {render + "raycast --view nan,20,4", "--view", "'nan,20,4'", "expected"},
                         {render + "raycast --view 30,20,inf", "--view", "'30,20,inf'", "expected"},
                         {render + "half-angle --light 1e300,45", "--light", "'1e300,45'", "azimuth"},
                         {render + "half-angle --light 30,nan", "--light", "'30,nan'", "expected"},
                         {render + "raycast --gpu-budget 0.5", "--gpu-budget", "'0.5'", "positive size"}, // was 0 bytes
                         {render + "raycast --gpu-budget nan", "--gpu-budget", "'nan'", "positive size"},
                         {render + "raycast --gpu-budget inf", "--gpu-budget", "'inf'", "positive size"},
                         {render + "raycast --device -5", "--device", "'-5'", "not in [-1, 1023]"}, // was drawn on llvmpipe
                         {render + "raycast --device 1.5", "--device", "'1.5'", "not a whole number"},
                         {render + "raycast --region 1.5", "--region", "'1.5'", "not a whole number"},
                         {render + "raycast --region nan", "--region", "'nan'", "not a whole number"},
                         {render + "raycast --region -1", "--region", "'-1'", "not in [0, "},
                         {render + "raycast --repeat 1.5", "--repeat", "'1.5'", "not a whole number"},
                         {render + "raycast --repeat 0", "--repeat", "'0'", "not in [1, 1000]"},
                         {render + "texture-slicing --slices 1.5", "--slices", "'1.5'", "not a whole number"},
                         {render + "texture-slicing --slices -1", "--slices", "'-1'", "not in [0, 100000]"},
                         {"inspect {V} -o {O}/out.png --render raycast --size 40.5x30", "--size", "'40.5x30'", "expected"},
                         {render + "cut --cut z:nan", "--cut", "'z:nan'", "expected"},
                         {render + "cut --cut z:1.5", "--cut", "'z:1.5'", "expected"},
                         {render + "cut --cut z:-4", "--cut", "z:-4", "outside the volume"},
                         // Volumetric triangles ignored nan before.
                         {preview + "--yarn-radius nan", "--yarn-radius", "'nan'", "not a finite number"},
                         {preview + "--yarn-radius inf", "--yarn-radius", "'inf'", "not a finite number"},
                         {preview + "--yarn-radius 0", "--yarn-radius", "'0'", "not a positive length"},
                         {preview + "--yarn-radius 1e30", "--yarn-radius", "'1e30'", "1e12"},
                         {preview + "--slice-spacing nan", "--slice-spacing", "'nan'", "not a finite number"},
                         {preview + "--slice-spacing 1e-30", "--slice-spacing", "'1e-30'", "1e-12"},
                         {preview + "--resolution 64.5", "--resolution", "'64.5'", "not a whole number"}, // was "not in range"
                         {preview + "--resolution 4", "--resolution", "'4'", "not in [8, "},
                         {preview + "--slices-per-segment 2.5", "--slices-per-segment", "'2.5'", "not a whole number"},
                         {"inspect {V} --mesh {O}/out.ply --iso nan", "--iso", "'nan'", "not a finite number"},
                         {"inspect {V} --mesh {O}/out.ply --mesh-level 1.5", "--mesh-level", "'1.5'", "not a whole number"},
                         {"inspect {V} --mesh {O}/out.ply --mesh-level -1", "--mesh-level", "'-1'", "not in [0, 20]"},
                         {"inspect {V} --html {O}/report --html-renders 1.5", "--html-renders", "'1.5'", "not a whole number"},
                         {"inspect {V} --html {O}/report --html-renders -1", "--html-renders", "'-1'", "not in [0, 10000]"},
                     });
    CHECK(yv::test::runYarnvox("inspect " + v.work + " --limit 0").exitCode == 0);
}

TEST_CASE("bad input: export's numbers and boxes are refused naming the option and the value", "[bad-input][cli]") {
    const Volume v;
    const std::string exp = "export {V} -o {O}/out.vol ";
    expectRefused(v, {
                         {exp + "--sggx nan", "--sggx", "'nan'", "not a finite number"}, // exit 0 without the file before
                         {exp + "--sggx inf", "--sggx", "'inf'", "not a finite number"},
                         {exp + "--sggx -inf", "--sggx", "'-inf'", "not a finite number"},
                         {exp + "--sggx 0", "--sggx", "'0'", "not in [1e-06, 1]"},
                         {exp + "--sggx 2", "--sggx", "'2'", "not in [1e-06, 1]"},
                         // Boxes of no voxel of the volume exported a box of zeros, exit 0.
                         {exp + "--bbox 1000,1000,1000,1010,1010,1010", "--bbox", "1000,1000,1000,1010,1010,1010",
                          "none of the volume's"},
                         {exp + "--bbox -20,-20,-20,-10,-10,-10", "--bbox", "-20,-20,-20,-10,-10,-10", "none of the volume's"},
                         {exp + "--bbox 0,0,1000,64,64,1010", "--bbox", "0,0,1000,64,64,1010", "none of the volume's"},
                         {exp + "--bbox-world 1000,1000,1000,1010,1010,1010", "--bbox-world", "1000,1000,1000,1010,1010,1010",
                          "none of the volume's"},
                         {exp + "--bbox-world -90,-90,-90,-80,-80,-80", "--bbox-world", "-90,-90,-90,-80,-80,-80", "none of the volume's"},
                         {exp + "--bbox nan,0,0,4,4,4", "--bbox", "nan,0,0,4,4,4", "expected six numbers"},
                         {exp + "--bbox 0,0,0,4,4,4.5", "--bbox", "0,0,0,4,4,4.5", "whole numbers"},
                         {exp + "--bbox-world 0,0,0,1,1,inf", "--bbox-world", "0,0,0,1,1,inf", "expected six numbers"},
                         {exp + "--region 1.5 --work-dir {W}", "--region", "'1.5'", "not a whole number"},
                         {exp + "--region nan --work-dir {W}", "--region", "'nan'", "not a whole number"},
                     });
    // A box that holds part of the volume, and a roughness in range: written.
    const fs::path out = v.dir.path / "part.vol";
    const yv::test::RunResult r =
        yv::test::runYarnvox("export " + v.vdb + " -o " + out.string() + " --bbox -8,-8,-8,20,20,20 --sggx 0.5 --quiet");
    INFO(r.output);
    CHECK(r.exitCode == 0);
    CHECK(fs::exists(out));
    CHECK(fs::exists(v.dir.path / "part.sggx.vol"));
}

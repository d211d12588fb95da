// Runs that cannot fit the disk do not start: once the slices lie on the
// grid, the output a run is expected to write is compared with the free
// space of its file systems, and a run that would not fit is refused with
// the numbers and what to change. YARNVOX_TEST_FREE_BYTES stands a small
// disk in for the real one. docs/reliability.md lists them.
#include "bcc.h"

#include "garment/cross_section.h"
#include "garment/curve_check.h"
#include "plan/grid.h"
#include "plan/resource_estimate.h"
#include "run_cli.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

/// YARNVOX_TEST_FREE_BYTES for this process while it lives.
struct FreeBytes {
    explicit FreeBytes(double bytes) { ::setenv("YARNVOX_TEST_FREE_BYTES", std::to_string(bytes).c_str(), 1); }
    ~FreeBytes() { ::unsetenv("YARNVOX_TEST_FREE_BYTES"); }
};

/// The garment file planned as `voxelize FILE --resolution R` plans it (the
/// file's radius, one slice a voxel, the default fibre cross-section).
struct PlannedRun {
    yv::Garment garment;
    yv::SlicePlan plan;
    yv::VoxelGrid grid;
    yv::CrossSection xs = yv::makeFiberCrossSection();
    PlannedRun(const std::string& path, int resolution) : garment(yv::readBcc(path)) {
        yv::checkCurves(garment, path);
        yv::SliceOptions opt;
        opt.radius = garment.yarnRadius;
        opt.spacing = yv::defaultSliceSpacing(yv::voxelSizeFor(garment, opt.radius, resolution, 0.0), 1);
        plan = yv::planSlices(garment, opt);
        grid = yv::makeGrid(plan, resolution, 0.0);
    }
    yv::OutputPlan output(const yv::VdbShape& shape = {}) const { return yv::outputPlan(plan, grid, xs, shape); }
};

} // namespace

TEST_CASE("Disk estimate: a yarn's voxels from its length and grown cross-section, the bytes from how they are stored",
          "[disk-estimate]") {
    // The disk: pi r^2 + 4 r h + h^2, a disk grown by a square voxel face.
    const yv::CrossSection disk = yv::makeDiskCrossSection();
    CHECK(yv::grownFibreArea(disk, 0.3, 0.1) == Approx(M_PI * 0.09 + 0.12 + 0.01));
    // A fibre texture: its fibre texels when the voxels are far finer, its
    // gaps filled as they grow, never more than the grown square.
    const yv::CrossSection fibres = yv::makeFiberCrossSection();
    double filled = 0.0;
    for (std::uint8_t d : fibres.density) filled += d != 0;
    const double texel = 2.0 * 0.3 / fibres.size;
    CHECK(yv::grownFibreArea(fibres, 0.3, 1e-6) == Approx(filled * texel * texel));
    double before = 0.0;
    for (double h : {0.001, 0.01, 0.03, 0.1, 0.3, 1.0}) {
        const double area = yv::grownFibreArea(fibres, 0.3, h);
        CHECK(area >= before);
        CHECK(area <= (0.6 + h) * (0.6 + h) + 1e-12);
        before = area;
    }
    CHECK(yv::grownFibreArea(fibres, 0.3, 0.1) < yv::grownFibreArea(disk, 0.3, 0.1));
    // On a small random mask, the texels a brute-force dilation finds: every
    // texel of the padded grid with a fibre texel at most `grow` before it
    // along both axes.
    {
        yv::CrossSection random;
        random.size = 23;
        random.density.resize(23 * 23);
        std::uint32_t x = 7;
        for (std::uint8_t& d : random.density) d = (x = x * 1664525u + 1013904223u) >> 29 == 0 ? 255 : 0;
        for (int grow : {0, 1, 2, 5, 30}) {
            const double texelSide = 2.0 * 0.3 / 23;
            const int m = 23 + grow;
            std::size_t texels = 0;
            for (int ty = 0; ty < m; ++ty)
                for (int tx = 0; tx < m; ++tx) {
                    bool near = false;
                    for (int sy = std::max(0, ty - grow); sy <= std::min(22, ty) && !near; ++sy)
                        for (int sx = std::max(0, tx - grow); sx <= std::min(22, tx) && !near; ++sx)
                            near = random.density[std::size_t(sy) * 23 + sx] != 0;
                    texels += near;
                }
            INFO("grow " << grow);
            CHECK(yv::grownFibreArea(random, 0.3, grow * texelSide) == Approx(texels * texelSide * texelSide));
        }
    }

    yv::OutputPlan run;
    run.yarnLength = 100.0;
    run.radius = 0.3;
    run.voxelSize = 0.1;
    const double voxels = 100.0 * (M_PI * 0.09 + 0.12 + 0.01) / 1e-3;
    const yv::ExpectedOutput e = yv::expectOutput(run);
    CHECK(e.activeVoxels == Approx(voxels));
    CHECK(e.vdbBytes == Approx(18.0 * voxels)); // 16 bytes of values, a byte of leaf a grid
    CHECK(e.regionBytes == Approx(18.0 * voxels));
    run.shape.halfPrecision = true;
    CHECK(yv::expectOutput(run).vdbBytes == Approx(10.0 * voxels));
    CHECK(yv::expectOutput(run).regionBytes == Approx(18.0 * voxels)); // the regions hold floats
    run.shape = {false, true, 0};
    CHECK(yv::expectOutput(run).vdbBytes == Approx(31.0 * voxels));
    run.shape = {false, false, 2};
    CHECK(yv::expectOutput(run).vdbBytes == Approx(18.0 * voxels * (1.0 + 0.25 + 0.0625)));
    // The preview pyramid (levels 3 to 11) adds about 2 %, not the third a full pyramid would.
    run.shape = {false, false, 11, 3};
    double preview = 1.0;
    for (int l = 3; l <= 11; ++l) preview += std::pow(0.25, l);
    CHECK(yv::expectOutput(run).vdbBytes == Approx(18.0 * voxels * preview));
    CHECK(preview < 1.025);
}

TEST_CASE("Disk estimate: refused without a 5 % margin, with the bytes, the free space and a grid that fits",
          "[disk-estimate]") {
    yv::OutputPlan run;
    run.yarnLength = 1e5;
    run.radius = 0.3;
    run.voxelSize = 0.01;
    const double need = 2.0 * yv::expectOutput(run).vdbBytes; // the .vdb and its scratch file
    const yv::RunPlace place{fs::temp_directory_path().string(), ""};
    {
        const FreeBytes free(need * 1.06 + 1e6);
        CHECK(yv::checkExpectedDisk(run, place, "--resolution 4096").empty());
    }
    {
        const FreeBytes free(need * 1.04 + 1e6);
        CHECK_FALSE(yv::checkExpectedDisk(run, place, "--resolution 4096").empty());
    }
    const FreeBytes free(need * 0.7);
    const std::string why = yv::checkExpectedDisk(run, place, "--resolution 4096");
    INFO(why);
    char needText[32], freeText[32];
    std::snprintf(needText, sizeof needText, "%.3g GB", need / 1e9);
    std::snprintf(freeText, sizeof freeText, "%.3g GB", need * 0.7 / 1e9);
    CHECK_THAT(why, Contains("with --resolution 4096 the run is expected to write " + std::string(needText)) &&
                        Contains(std::string(freeText) + " free") && Contains("nothing was voxelized") &&
                        Contains("--precision half (16-bit values) fits"));
    // The grid it offers fits, and one a little finer does not.
    const std::size_t at = why.find("; or --resolution ");
    REQUIRE(at != std::string::npos);
    const int offered = std::atoi(why.c_str() + at + 18);
    REQUIRE(offered > 8);
    REQUIRE(offered < 4096);
    yv::OutputPlan coarser = run;
    coarser.voxelSize = run.voxelSize * 4096.0 / offered;
    CHECK(yv::checkExpectedDisk(coarser, place, "--resolution " + std::to_string(offered)).empty());
    coarser.voxelSize = run.voxelSize * 4096.0 / (offered * 1.01);
    CHECK_FALSE(yv::checkExpectedDisk(coarser, place, "--resolution 4096").empty());
    // With --voxel-size, a voxel size; a run already in half precision is not told to use it.
    run.shape.halfPrecision = true;
    const FreeBytes tiny(need * 0.1);
    CHECK_THAT(yv::checkExpectedDisk(run, place, "--voxel-size 0.01"),
               Contains("--voxel-size ") && Contains("or coarser") && !Contains("--precision half"));
    // The work dir's regions count where it shares the output's file system,
    // also one not made yet (its parent's file system).
    run.shape.halfPrecision = false;
    const FreeBytes just(need * 1.06 + 1e6);
    CHECK(yv::checkExpectedDisk(run, place, "--resolution 4096").empty());
    for (const std::string& work : {place.outputDir, place.outputDir + "/not-made-yet/work"})
        CHECK_THAT(yv::checkExpectedDisk(run, {place.outputDir, work}, "--resolution 4096"),
                   Contains("and the work dir's regions"));
}

TEST_CASE("bad input: a run whose expected output does not fit the disk is refused before voxelizing, with the numbers",
          "[bad-input][cli]") {
    yv::test::ScratchDir dir("yv_disk_estimate");
    const std::string bcc = (dir.path / "g.bcc").string(), vdb = (dir.path / "g.vdb").string();
    REQUIRE(yv::test::runYarnvox("gen --pattern knit --shape cylinder --crossings 400 --quiet -o " + bcc).exitCode == 0);
    const PlannedRun planned(bcc, 256);
    const double need = 2.0 * yv::expectOutput(planned.output()).vdbBytes;
    // The bound checked before slicing lets this disk through: only the
    // estimate made after planning refuses it.
    const double bound = 2.0 * yv::estimateNeeds(planned.garment, planned.garment.yarnRadius, planned.grid.voxelSize, false).outputBytes;
    REQUIRE(bound < 0.5 * need);

    const auto voxelize = [&](double free, const std::string& more) {
        return yv::test::runShell("YARNVOX_TEST_FREE_BYTES=" + std::to_string(free) + " " + YV_BINARY_DIR + "/yarnvox voxelize " +
                                  bcc + " -o " + vdb + " --backend cpu --resolution 256 " + more);
    };
    const fs::path work = dir.path / "work";
    const auto start = std::chrono::steady_clock::now();
    // A float run (the estimate above is float's; the default, half, needs about half of it).
    yv::test::RunResult r = voxelize(0.8 * need, "--precision float --work-dir " + work.string());
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    INFO(r.output);
    CHECK(r.exitCode == 1);
    CHECK_THAT(r.output, Contains("yarnvox: error: " + bcc + ": with --resolution 256 the run is expected to write ") &&
                             Contains(" free") && Contains("nothing was voxelized") && Contains("--resolution "));
    CHECK(std::count(r.output.begin(), r.output.end(), '\n') == 1);
    CHECK(seconds < 20.0);
    CHECK_FALSE(fs::exists(vdb));
    CHECK_FALSE(fs::exists(work)); // refused before the work dir was made
    for (const auto& e : fs::directory_iterator(dir.path)) CHECK(e.path().filename().string().find(".partial-") == std::string::npos);

    // Without the work dir's full-precision regions: what it offers works on
    // the same disk, half precision or the grid it names.
    r = voxelize(0.8 * need, "--precision float --quiet");
    CHECK(r.exitCode == 1);
    CHECK_THAT(r.output, Contains("--precision half (16-bit values) fits"));
    const std::size_t at = r.output.find("; or --resolution ");
    REQUIRE(at != std::string::npos);
    const std::string offered = std::to_string(std::atoi(r.output.c_str() + at + 18));
    r = yv::test::runShell("YARNVOX_TEST_FREE_BYTES=" + std::to_string(0.8 * need) + " " + YV_BINARY_DIR + "/yarnvox voxelize " +
                           bcc + " -o " + vdb + " --backend cpu --precision float --quiet --resolution " + offered);
    INFO("--resolution " << offered << "\n" << r.output);
    CHECK(r.exitCode == 0);
    fs::remove(vdb);
    r = voxelize(0.8 * need, "--precision half --quiet");
    CHECK(r.exitCode == 0);
    CHECK(fs::exists(vdb));
    fs::remove(vdb);
    r = voxelize(0.8 * need, "--quiet"); // the default is half
    CHECK(r.exitCode == 0);
    CHECK(fs::exists(vdb));
    fs::remove(vdb);

    // Room for it: written, and the .vdb is no larger than expected (the
    // estimate errs high where yarns touch, never far low).
    r = voxelize(1.2 * need, "--precision float --quiet");
    CHECK(r.exitCode == 0);
    REQUIRE(fs::exists(vdb));
    CHECK(double(fs::file_size(vdb)) <= 1.05 * need / 2.0);
}

// voxelize --bbox and --bbox-world: a box of the garment on the whole run's
// grid. Per voxel, a box run is the whole run restricted to the box (density,
// axis and albedo, bit for bit) and writes nothing outside it, on both
// backends, in memory and through a work dir, merged and resumed; it draws
// fewer slices; its bad input is one line, a non-zero exit and no file.
#include "bbox_runs.h"
#include "gpu/gl_voxelizer.h"
#include "plan/zoom_plan.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <map>
#include <numeric>
#include <string>

namespace fs = std::filesystem;
using namespace yv;
using test::BoxFixture;
using test::TestBox;

namespace {

/// The whole run and a run of the cutting box, in memory, with their stats;
/// checks the box run voxel by voxel and that it did less work.
void checkBoxRunOn(const std::string& backend) {
    const BoxFixture f(backend);
    const fs::path whole = f.path("whole.vdb"), wholeStats = f.path("whole.json");
    f.voxelize(whole, "--stats " + wholeStats.string());
    const nlohmann::json ws = test::readStats(wholeStats);
    const TestBox box = BoxFixture::cuttingBox(BoxFixture::dims(ws));
    const fs::path part = f.path("box.vdb"), partStats = f.path("box.json");
    f.voxelize(part, "--bbox " + box.text() + " --stats " + partStats.string());

    const test::BoxTestVoxels wholeVoxels = test::readActiveVoxels(whole);
    std::uint64_t onFaces = 0;
    const std::uint64_t matched = test::checkBoxIsWholeRestricted(wholeVoxels, test::readActiveVoxels(part), box, &onFaces);
    // The box holds part of the garment, and its faces cut through yarns.
    CHECK(matched > 500);
    CHECK(matched < wholeVoxels.size() / 2);
    CHECK(onFaces > 50);

    // Less work: fewer regions, samples and slices than the whole run.
    const nlohmann::json bs = test::readStats(partStats);
    CHECK(bs["bbox"]["voxels"] == box.text());
    CHECK(bs["bbox"]["clipped"] == false);
    CHECK(bs["bbox"]["slices_reaching"].get<std::uint64_t>() < ws["slices"].get<std::uint64_t>() / 2);
    CHECK(bs["backend_stats"]["zoom_regions"].get<std::uint64_t>() < ws["backend_stats"]["zoom_regions"].get<std::uint64_t>());
    CHECK(bs["samples"].get<std::uint64_t>() < ws["samples"].get<std::uint64_t>() / 2);
    if (backend == "gl")
        CHECK(bs["backend_stats"]["slices_drawn"].get<std::uint64_t>() <
              ws["backend_stats"]["slices_drawn"].get<std::uint64_t>() / 2);
    CHECK(bs["active_voxels"] == matched);
}

} // namespace

TEST_CASE("Bbox: the zoom plan of a box covers exactly its voxels, in regions of whole bricks", "[bbox][zoom]") {
    const test::GeneratedRun run = test::generatedRun(WeavePattern::Twill, GarmentShape::Flat, 100, 0.0, 96);
    const CrossSection xs = makeCrossSection("fibers", false);
    const std::optional<VoxelBox> box = VoxelBox{{13, 21, 3}, {61, 50, run.grid.dims.z - 2}};
    const ZoomPlan plan = planZoomRegions(run.plan, run.grid, xs, {2000, 1024, 1}, box);
    const ZoomPlan wholePlan = planZoomRegions(run.plan, run.grid, xs, {2000, 1024, 1});
    REQUIRE(plan.regions.size() > 1);
    CHECK(plan.regions.size() < wholePlan.regions.size());
    std::uint64_t covered = 0;
    for (const ZoomRegion& r : plan.regions) {
        for (int a = 0; a < 3; ++a) {
            CHECK(r.min[a] % 8 == 0);
            CHECK(r.max[a] % 8 == 0);
        }
        const VoxelBox kept = intersect({r.min, r.max}, *box);
        REQUIRE(!kept.empty());
        covered += std::uint64_t(kept.dims().x) * kept.dims().y * kept.dims().z;
        // A region's segments are every one that reaches its voxels in the box.
        std::vector<std::uint32_t> all(run.plan.segments.size());
        std::iota(all.begin(), all.end(), 0u);
        CHECK(r.segments == segmentsReaching(run.plan, run.grid, all, kept.min, kept.max));
    }
    // Regions are disjoint, so covering the box's voxel count means covering the box
    // (where no segment reaches, a part may be left out: none here).
    const glm::ivec3 d = box->dims();
    CHECK(covered == std::uint64_t(d.x) * d.y * d.z);
}

TEST_CASE("Bbox (CPU): a box run is the whole run inside the box, voxel for voxel, and nothing outside", "[bbox][cli]") {
    checkBoxRunOn("cpu");
}

TEST_CASE("Bbox (GL): a box run is the whole run inside the box, voxel for voxel, and nothing outside", "[bbox][gl][cli]") {
    YV_REQUIRE_GL();
    checkBoxRunOn("gl");
}

TEST_CASE("Bbox: --bbox-world gives the voxels of the same box in voxel indices", "[bbox][cli]") {
    const BoxFixture f("cpu");
    const fs::path whole = f.path("whole.vdb"), stats = f.path("whole.json");
    f.voxelize(whole, "--stats " + stats.string());
    const TestBox box = BoxFixture::cuttingBox(BoxFixture::dims(test::readStats(stats)));
    // Voxel i covers origin + [i, i+1) h; the .vdb puts voxel i's centre at origin + (i + 0.5) h.
    const FiberGrids grids = readFiberGrids(whole.string());
    const double h = grids.density->voxelSize()[0];
    const openvdb::Vec3d centre0 = grids.density->indexToWorld(openvdb::Coord(0, 0, 0));
    std::string world;
    for (int i = 0; i < 6; ++i) {
        const int a = i % 3;
        // A quarter voxel inside the box's outer voxels: every cell it overlaps is the box's.
        const double index = i < 3 ? box.min[a] + 0.25 : box.max[a] - 0.25;
        world += (i ? "," : "") + std::to_string(centre0[a] - 0.5 * h + index * h);
    }
    const fs::path byIndex = f.path("index.vdb"), byWorld = f.path("world.vdb"), worldStats = f.path("world.json");
    f.voxelize(byIndex, "--bbox " + box.text());
    f.voxelize(byWorld, "--bbox-world " + world + " --stats " + worldStats.string());
    CHECK(test::readStats(worldStats)["bbox"]["voxels"] == box.text());
    const test::BoxTestVoxels a = test::readActiveVoxels(byIndex), b = test::readActiveVoxels(byWorld);
    REQUIRE(a.size() > 500);
    CHECK(a == b);
}

TEST_CASE("Bbox: a box partly outside the grid is clipped to it, said under --verbose and in --stats", "[bbox][cli]") {
    const BoxFixture f("cpu");
    const fs::path whole = f.path("whole.vdb"), stats = f.path("whole.json");
    f.voxelize(whole, "--stats " + stats.string());
    const std::array<int, 3> d = BoxFixture::dims(test::readStats(stats));
    const fs::path part = f.path("clipped.vdb"), partStats = f.path("clipped.json");
    const std::string asked = "-20,-7,-3," + std::to_string(d[0] / 3 + 1) + "," + std::to_string(d[1] / 2 + 3) + ",1000";
    // --verbose speaks only without --quiet.
    std::string options = f.options;
    options.erase(options.find(" --quiet"), 8);
    const test::RunResult r = test::runYarnvox("voxelize " + f.bcc + " -o " + part.string() + options +
                                               " --bbox=" + asked + " --verbose --stats " + partStats.string());
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    CHECK_THAT(r.output, Catch::Contains("--bbox " + asked + " reaches past the grid") && Catch::Contains("clipped"));
    const TestBox box{{0, 0, 0}, {d[0] / 3 + 1, d[1] / 2 + 3, d[2]}};
    const nlohmann::json bs = test::readStats(partStats);
    CHECK(bs["bbox"]["clipped"] == true);
    CHECK(bs["bbox"]["voxels"] == box.text());
    CHECK(bs["bbox"]["asked"] == "--bbox " + asked);
    CHECK(test::checkBoxIsWholeRestricted(test::readActiveVoxels(whole), test::readActiveVoxels(part), box) > 500);
}

TEST_CASE("Bbox (GL): with the GPU's brick resolve too, a box keeps the whole run's voxels and none outside it",
          "[bbox][gl]") {
    YV_REQUIRE_GL();
    const test::GeneratedRun run = test::generatedRun(WeavePattern::Twill, GarmentShape::Flat, 60, 2.0, 64);
    const CrossSection xs = makeCrossSection("fibers");
    const GlContext context;
    GlVoxelizeSettings settings;
    settings.brickResolve = BrickResolve::Gpu; // what a GPU runs; llvmpipe resolves on the host by default
    const BrickVolume whole = voxelizeGl(run.plan, xs, run.grid, settings, context);
    const glm::ivec3 d = run.grid.dims;
    const VoxelBox box{{11, 7, d.z / 2 - 1}, {45, 37, d.z - 3}};
    settings.base.clip = box;
    const BrickVolume part = voxelizeGl(run.plan, xs, run.grid, settings, context);

    std::map<std::uint64_t, const VoxelBrick*> wholeBricks;
    for (const VoxelBrick& b : whole.bricks) wholeBricks[b.key] = &b;
    std::uint64_t kept = 0, expected = 0;
    for (const VoxelBrick& b : part.bricks)
        for (int v = 0; v < kBrickVoxels; ++v) {
            if (!b.isActive(v)) continue;
            const glm::ivec3 voxel = brickCoord(b.key) * 8 + glm::ivec3(v >> 6, (v >> 3) & 7, v & 7);
            INFO("voxel " << voxel.x << "," << voxel.y << "," << voxel.z);
            REQUIRE(box.contains(voxel));
            REQUIRE(wholeBricks.count(b.key) == 1);
            const VoxelBrick& w = *wholeBricks[b.key];
            REQUIRE(w.isActive(v));
            REQUIRE(b.density[v] == w.density[v]);
            REQUIRE(b.orientation[v] == w.orientation[v]);
            ++kept;
        }
    for (const VoxelBrick& b : whole.bricks)
        for (int v = 0; v < kBrickVoxels; ++v)
            expected += b.isActive(v) && box.contains(brickCoord(b.key) * 8 + glm::ivec3(v >> 6, (v >> 3) & 7, v & 7));
    CHECK(kept == expected);
    CHECK(kept > 300);
}

// A .vdb's view voxelizes what the camera sees as the run that made it did:
// its garment, found where the run recorded it, with the options the run
// recorded (cross-section, twist, supersampling...), equal voxel for voxel
// to `yarnvox voxelize` with the command the view gives; a .vdb whose
// garment is gone is drawn as before and says why it cannot voxelize.
#include "bbox_runs.h"
#include "inspect/run_slices.h"
#include "served_view.h"
#include "view/view_volume.h"

#include <catch2/catch.hpp>

#include <string>

namespace fs = std::filesystem;
using Json = nlohmann::json;
using yv::test::Page;
using yv::test::ServedView;

TEST_CASE("View: a .vdb whose garment is found voxelizes what the camera sees as its run did, equal to yarnvox voxelize "
          "of the box with the run's options",
          "[view][gl]") {
    YV_REQUIRE_GL();
    ServedView view(false, [](yv::ViewRequest& r) {
        // Made with options other than the defaults, and viewed without them.
        const fs::path vdb = fs::path(r.saveDir) / "made.vdb";
        REQUIRE(yv::test::runYarnvox("voxelize " + r.input + " --resolution 48 --cross-section disk --twist 0.4 "
                                     "--supersample 2 --quiet -o " + vdb.string())
                    .exitCode == 0);
        r.input = vdb.string();
        r.maxSideVoxels = 96;
    });
    Page page(view.port.get_future().get());
    INFO(page.hello.dump());
    REQUIRE(page.hello["voxelSize"].is_number());
    CHECK(page.hello["sideBySide"] == false);
    CHECK(page.hello["twist"] == 0.4); // the run's twist, which the page may change
    std::uint64_t seq = 0;
    page.sendCamera(30, 20, 0.5, ++seq);
    CHECK(page.frameOf(seq).first["pixelUnits"] == "world");

    page.send(R"({"type":"voxelize-view"})");
    const Json asked = page.voxelizeMessages[yv::test::waitForVoxelize(page, "asked", seq, 0)];
    Json stats;
    for (;;) {
        page.sendCamera(30, 20, 0.5, ++seq);
        stats = page.frameOf(seq).first;
        if (stats["detail"].is_object() && stats["detail"]["shown"] == true) break;
    }
    const Json detail = stats["detail"];
    CHECK(std::stod(detail["voxelSize"].get<std::string>()) < page.hello["voxelSize"].get<double>());
    const std::string command = yv::test::joined(detail["command"]);
    INFO(command);
    // The run's options, read back from the .vdb, are in the command.
    CHECK(command.find("plain.bcc") != std::string::npos);
    CHECK(command.find("--cross-section disk") != std::string::npos);
    CHECK(command.find("--twist 0.4") != std::string::npos);
    CHECK(command.find("--supersample 2") != std::string::npos);
    CHECK(command.find("--bbox-world " + asked["bboxWorld"].get<std::string>()) != std::string::npos);

    page.send(R"({"type":"save-view"})");
    const Json saved = page.voxelizeMessages[yv::test::waitForVoxelize(page, "saved", seq, 0)];
    const fs::path cliVdb = view.scratch.path / "cli.vdb";
    REQUIRE(yv::test::runYarnvox(command + " --quiet -o " + cliVdb.string()).exitCode == 0);
    const yv::test::BoxTestVoxels shown = yv::test::readActiveVoxels(saved["vdb"].get<std::string>());
    CHECK(shown.size() > 100);
    CHECK(shown == yv::test::readActiveVoxels(cliVdb));
    // And it is not what the default options give for the same box.
    const fs::path plainVdb = view.scratch.path / "plain-options.vdb";
    const std::string bcc = (view.scratch.path / "plain.bcc").string();
    REQUIRE(yv::test::runYarnvox("voxelize " + bcc + " --voxel-size " + asked["voxelSize"].get<std::string>() +
                                 " --bbox-world " + asked["bboxWorld"].get<std::string>() + " --quiet -o " +
                                 plainVdb.string())
                .exitCode == 0);
    CHECK_FALSE(shown == yv::test::readActiveVoxels(plainVdb));
    CHECK(page.notices.empty());
    CHECK(!view.failure);
}

TEST_CASE("View: a .vdb whose garment is gone is drawn, measures in voxels and says why it cannot voxelize", "[view][gl]") {
    YV_REQUIRE_GL();
    ServedView view(false, [](yv::ViewRequest& r) {
        const fs::path dir = fs::path(r.saveDir);
        fs::copy_file(r.input, dir / "gone.bcc");
        REQUIRE(yv::test::runYarnvox("voxelize " + (dir / "gone.bcc").string() + " --resolution 32 --quiet -o " +
                                     (dir / "gone.vdb").string())
                    .exitCode == 0);
        fs::remove(dir / "gone.bcc");
        r.input = (dir / "gone.vdb").string();
    });
    Page page(view.port.get_future().get());
    CHECK(page.hello["voxelSize"].is_null());
    std::uint64_t seq = 0;
    page.sendCamera(30, ++seq);
    CHECK(page.frameOf(seq).first["pixelUnits"] == "voxels");
    page.send(R"({"type":"voxelize-view"})");
    page.sendCamera(30, ++seq);
    page.frameOf(seq);
    REQUIRE(page.notices.size() == 1);
    CHECK(page.notices[0].find("needs the garment") != std::string::npos);
    CHECK(view.logged("no voxelizing what the camera sees"));
    CHECK(!view.failure);
}

TEST_CASE("View: a .vdb or work directory made with --albedo voxelizes the view with its colour, one without it without",
          "[view]") {
    yv::test::ScratchDir scratch("yv_view_albedo");
    const fs::path bcc = scratch.path / "plain.bcc";
    REQUIRE(yv::test::runYarnvox("gen --pattern plain --crossings 4 --quiet -o " + bcc.string()).exitCode == 0);
    const fs::path png = yv::test::writeTwoColourPng(scratch.path / "colour.png", 16);

    const std::string common = "voxelize " + bcc.string() + " --cross-section " + png.string() + " --resolution 24 --quiet ";
    const fs::path coloured = scratch.path / "coloured.vdb", work = scratch.path / "coloured.work",
                   plain = scratch.path / "plain.vdb";
    REQUIRE(yv::test::runYarnvox(common + "--albedo -o " + coloured.string()).exitCode == 0);
    REQUIRE(yv::test::runYarnvox(common + "--albedo --work-dir " + work.string() + " -o " +
                                 (scratch.path / "from-work.vdb").string())
                .exitCode == 0);
    REQUIRE(yv::test::runYarnvox(common + "-o " + plain.string()).exitCode == 0);

    const yv::VoxelizeJob view;
    for (const fs::path& path : {coloured, work, plain}) {
        INFO(path);
        const yv::VoxelizeJob job = yv::recordedVoxelizeJob(yv::loadRunSlices(path.string(), {}), view, path.string());
        CHECK(job.albedo == (path != plain));
        CHECK(job.crossSection == png.string());
        CHECK(job.input == bcc.string());
    }
}

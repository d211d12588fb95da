// Voxelize what the camera sees, end to end in-process: a page of a garment's
// view zooms in and asks (as the page does when the camera stops); the run
// is drawn in the ray cast's place while the camera sees no more than its
// box, and the volume opened again when it sees more; saved, its .vdb equals
// `yarnvox voxelize` with the command the view gives, voxel for voxel; saved
// as a work directory, `inspect` and `merge` read it.
#include "bbox_runs.h"
#include "served_view.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <string>

namespace fs = std::filesystem;
using Json = nlohmann::json;
using yv::test::Page;
using yv::test::ServedView;
using yv::test::joined;
using yv::test::waitForVoxelize;
using yv::test::meanDifference;

TEST_CASE("View: what the camera sees is voxelized finer, drawn in place, and saved equal to yarnvox voxelize of its box",
          "[view][gl]") {
    YV_REQUIRE_GL();
    ServedView view(false, [](yv::ViewRequest& r) { r.maxSideVoxels = 96; });
    Page page(view.port.get_future().get());
    std::uint64_t seq = 0;
    page.sendCamera(30, 20, 0.5, ++seq);
    const auto [before, coarse] = page.frameOf(seq);
    CHECK(before["detail"].is_null());

    page.send(R"({"type":"voxelize-view"})");
    const std::size_t askedAt = waitForVoxelize(page, "asked", seq, 0);
    const std::size_t runningAt = waitForVoxelize(page, "running", seq, 0);
    const Json asked = page.voxelizeMessages[askedAt], running = page.voxelizeMessages[runningAt];
    CHECK(running["bboxWorld"] == asked["bboxWorld"]);
    // Drawn in place once run: the frame says so and shows finer voxels.
    Json stats;
    yv::RgbImage fine;
    for (;;) {
        page.sendCamera(30, 20, 0.5, ++seq);
        std::tie(stats, fine) = page.frameOf(seq);
        if (stats["detail"].is_object() && stats["detail"]["shown"] == true) break;
    }
    const Json detail = stats["detail"];
    CHECK(detail["bboxWorld"] == asked["bboxWorld"]);
    CHECK(detail["voxelSize"] == asked["voxelSize"]);
    CHECK(detail["activeVoxels"].get<std::uint64_t>() > 0);
    // Finer than the volume opened (the garment at --resolution 48).
    REQUIRE(page.hello["voxelSize"].is_number());
    CHECK(std::stod(detail["voxelSize"].get<std::string>()) < page.hello["voxelSize"].get<double>());
    CHECK(meanDifference(coarse, fine) > 0.2);
    // The same camera asked again: nothing new to run.
    page.send(R"({"type":"voxelize-view"})");
    const std::size_t alreadyAt = waitForVoxelize(page, "already", seq, std::max(askedAt, runningAt) + 1);
    CHECK(page.voxelizeMessages[alreadyAt]["voxelSize"] == asked["voxelSize"]);

    // A camera that sees the whole garment sees more than the box: the volume opened is drawn.
    page.sendCamera(30, 20, 4, ++seq);
    CHECK(page.frameOf(seq).first["detail"]["shown"] == false);

    // Saved: the .vdb shown equals the command line's run of the same box, voxel for voxel.
    page.send(R"({"type":"save-view"})");
    const std::size_t savedAt = waitForVoxelize(page, "saved", seq, alreadyAt + 1);
    const Json saved = page.voxelizeMessages[savedAt];
    const fs::path savedVdb = saved["vdb"].get<std::string>();
    REQUIRE(fs::exists(savedVdb));
    CHECK(savedVdb.parent_path() == view.scratch.path);
    const fs::path cliVdb = view.scratch.path / "cli.vdb";
    const std::string command = joined(detail["command"]);
    CHECK(command.find("--bbox-world " + asked["bboxWorld"].get<std::string>()) != std::string::npos);
    CHECK(command.find("--voxel-size " + asked["voxelSize"].get<std::string>()) != std::string::npos);
    REQUIRE(yv::test::runYarnvox(command + " --quiet -o " + cliVdb.string()).exitCode == 0);
    const yv::test::BoxTestVoxels shown = yv::test::readActiveVoxels(savedVdb);
    const yv::test::BoxTestVoxels cli = yv::test::readActiveVoxels(cliVdb);
    CHECK(shown.size() == detail["activeVoxels"].get<std::uint64_t>());
    CHECK(shown.size() > 100);
    CHECK(shown == cli);

    // Saved through a work directory: inspect and merge read it.
    page.send(R"({"type":"save-view","workDir":true})");
    const Json savedWork = page.voxelizeMessages[waitForVoxelize(page, "saved", seq, savedAt + 1)];
    const std::string workDir = savedWork["workDir"].get<std::string>();
    REQUIRE(fs::is_directory(workDir));
    CHECK(yv::test::runYarnvox("inspect " + workDir).exitCode == 0);
    const fs::path merged = view.scratch.path / "merged.vdb";
    REQUIRE(yv::test::runYarnvox("merge " + workDir + " --quiet -o " + merged.string()).exitCode == 0);
    CHECK(yv::test::readActiveVoxels(merged) == cli);
    CHECK(page.notices.empty());
    CHECK(!view.failure);
}

TEST_CASE("View: the page's twist shades the slices and is what the camera's view is voxelized with, its transfer function "
          "changes the ray cast alone",
          "[view][gl]") {
    YV_REQUIRE_GL();
    ServedView view(false, [](yv::ViewRequest& r) { r.maxSideVoxels = 64; });
    Page page(view.port.get_future().get());
    REQUIRE(page.hello["twist"] == 0.0);
    REQUIRE(page.hello["yarnRadius"].get<double>() > 0.0);
    REQUIRE(page.hello["transferPresets"].size() >= 2);
    std::uint64_t seq = 0;
    page.sendCamera(30, 20, 0.5, ++seq);
    const yv::RgbImage plain = page.frameOf(seq).second;
    const int half = plain.width / 2;
    // The mean difference of one half, 16 pixels from the middle: the JPEG's
    // chroma, upsampled smoothly as it is decoded, reaches across the seam.
    const auto halfDifference = [&](const yv::RgbImage& a, const yv::RgbImage& b, bool left) {
        const int x0 = left ? 0 : half + 16, x1 = left ? half - 16 : a.width;
        double sum = 0.0;
        for (int y = 0; y < a.height; ++y)
            for (int x = x0; x < x1; ++x)
                for (int c = 0; c < 3; ++c) sum += std::abs(int(a.at(x, y)[c]) - int(b.at(x, y)[c]));
        return sum / double(a.height * (x1 - x0) * 3);
    };

    // A twist leaning the fibres 45 degrees at the yarn's surface: the slices
    // (left) shade differently, the ray cast of the density (right) does not.
    const double twist = 1.0 / page.hello["yarnRadius"].get<double>();
    page.send(Json{{"type", "twist"}, {"twist", twist}}.dump());
    page.sendCamera(30, 20, 0.5, ++seq);
    const auto [twistedStats, twisted] = page.frameOf(seq);
    CHECK(twistedStats["twist"] == twist);
    CHECK(halfDifference(plain, twisted, true) > 0.2);
    CHECK(halfDifference(plain, twisted, false) < 0.01);

    // Another transfer function: the ray cast changes, the slices do not; more opacity changes it again.
    page.send(R"({"type":"transfer","preset":"heat","opacity":1})");
    page.sendCamera(30, 20, 0.5, ++seq);
    const auto [heatStats, heat] = page.frameOf(seq);
    CHECK(heatStats["transfer"] == "heat");
    CHECK(halfDifference(twisted, heat, false) > 0.2);
    CHECK(halfDifference(twisted, heat, true) < 0.01);
    page.send(R"({"type":"transfer","preset":"heat","opacity":8})");
    page.sendCamera(30, 20, 0.5, ++seq);
    CHECK(halfDifference(heat, page.frameOf(seq).second, false) > 0.2);
    page.send(R"({"type":"transfer","preset":"fibre","opacity":1})");
    page.sendCamera(30, 20, 0.5, ++seq);
    CHECK(page.frameOf(seq).second.pixels == twisted.pixels);

    // Voxelized with the page's twist: the command says --twist and gives the same voxels, orientations included.
    page.send(R"({"type":"voxelize-view"})");
    const std::size_t askedAt = waitForVoxelize(page, "asked", seq, 0);
    CHECK(page.voxelizeMessages[askedAt]["twist"] == twist);
    Json stats;
    for (;;) {
        page.sendCamera(30, 20, 0.5, ++seq);
        stats = page.frameOf(seq).first;
        if (stats["detail"].is_object() && stats["detail"]["shown"] == true) break;
    }
    const std::string command = joined(stats["detail"]["command"]);
    INFO(command);
    CHECK(command.find(" --twist ") != std::string::npos);
    page.send(R"({"type":"save-view"})");
    const Json saved = page.voxelizeMessages[waitForVoxelize(page, "saved", seq, askedAt + 1)];
    const fs::path cliVdb = view.scratch.path / "twisted-cli.vdb";
    REQUIRE(yv::test::runYarnvox(command + " --quiet -o " + cliVdb.string()).exitCode == 0);
    const yv::test::BoxTestVoxels shown = yv::test::readActiveVoxels(saved["vdb"].get<std::string>());
    CHECK(shown.size() > 100);
    CHECK(shown == yv::test::readActiveVoxels(cliVdb));
    // ... and the twist is in them: without it the orientations differ.
    std::string untwisted = command.substr(0, command.find(" --twist "));
    const std::string rest = command.substr(command.find(" --twist ") + 9);
    untwisted += rest.find(' ') == std::string::npos ? "" : rest.substr(rest.find(' '));
    const fs::path plainVdb = view.scratch.path / "untwisted-cli.vdb";
    REQUIRE(yv::test::runYarnvox(untwisted + " --quiet -o " + plainVdb.string()).exitCode == 0);
    const yv::test::BoxTestVoxels straight = yv::test::readActiveVoxels(plainVdb);
    std::size_t axesDiffer = 0;
    for (const auto& [coord, voxel] : straight)
        if (const auto it = shown.find(coord); it != shown.end() && !(it->second.axis == voxel.axis)) ++axesDiffer;
    CHECK(axesDiffer > shown.size() / 10);
    CHECK(page.notices.empty());
    CHECK(!view.failure);
}

TEST_CASE("View: a large view is shown first from a coarse pass, then refined, and a save waits for the final pass", "[view][gl]") {
    YV_REQUIRE_GL();
    ServedView view(false, [](yv::ViewRequest& r) { r.maxSideVoxels = 256; });
    Page page(view.port.get_future().get());
    page.send(R"({"type":"size","width":640,"height":320})");
    std::uint64_t seq = 0;
    page.sendCamera(30, 20, 0.5, ++seq);
    page.frameOf(seq);
    page.send(R"({"type":"voxelize-view"})");
    const std::size_t askedAt = waitForVoxelize(page, "asked", seq, 0);
    const Json asked = page.voxelizeMessages[askedAt];
    INFO(asked.dump());
    REQUIRE(asked.contains("firstVoxelSize"));
    CHECK(std::stod(asked["firstVoxelSize"].get<std::string>()) == Approx(4.0 * std::stod(asked["voxelSize"].get<std::string>())).epsilon(0.01));
    Json firstShown, finalShown;
    for (;;) {
        page.sendCamera(30, 20, 0.5, ++seq);
        const Json stats = page.frameOf(seq).first;
        const Json& d = stats["detail"];
        if (!d.is_object() || d["shown"] != true) continue;
        if (d["final"] == false && firstShown.is_null()) {
            firstShown = d;
            // Shown, but not the run asked for: a save is refused until it is.
            page.send(R"({"type":"save-view"})");
        }
        if (d["final"] == true) {
            finalShown = d;
            break;
        }
    }
    REQUIRE(firstShown.is_object()); // shown as it refines: the coarse pass drawn before the final one
    CHECK(firstShown["voxelSize"] == asked["firstVoxelSize"]);
    CHECK(firstShown["bboxWorld"] == asked["bboxWorld"]);
    CHECK(finalShown["voxelSize"] == asked["voxelSize"]);
    CHECK(finalShown["id"].get<std::uint64_t>() > firstShown["id"].get<std::uint64_t>());
    CHECK(finalShown["activeVoxels"].get<std::uint64_t>() > firstShown["activeVoxels"].get<std::uint64_t>());
    // The save asked while the coarse pass was drawn: refused, or (the final
    // pass taken by a frame before the save was answered) the final pass saved;
    // never the coarse one.
    const auto refused = std::find_if(page.notices.begin(), page.notices.end(),
                                      [](const std::string& n) { return n.find("still being refined") != std::string::npos; });
    std::vector<std::uint64_t> savedIds;
    for (const Json& m : page.voxelizeMessages)
        if (m["state"] == "saving") savedIds.push_back(m["id"]);
    CHECK(std::find(savedIds.begin(), savedIds.end(), firstShown["id"].get<std::uint64_t>()) == savedIds.end());
    CHECK((refused != page.notices.end() ||
           (savedIds.size() == 1 && savedIds[0] == finalShown["id"].get<std::uint64_t>())));
    // Both passes ran (side by side: either may say so first).
    std::vector<std::string> passes;
    for (const Json& m : page.voxelizeMessages)
        if (m["state"] == "running") passes.push_back(m["pass"]);
    std::sort(passes.begin(), passes.end());
    CHECK(passes == std::vector<std::string>{"final", "first"});
    CHECK(!view.failure);
}

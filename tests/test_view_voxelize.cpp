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

namespace {

/// Reads frames until a voxelize message in `state` has arrived at index
/// `from` or later, and returns its index (or the view's watchdog ends the
/// wait). The answer to a request and the worker's "running" may come in
/// either order.
std::size_t waitForVoxelize(Page& page, const std::string& state, std::uint64_t& seq, std::size_t from) {
    for (;;) {
        for (std::size_t i = from; i < page.voxelizeMessages.size(); ++i) {
            const Json& m = page.voxelizeMessages[i];
            INFO(m.dump());
            REQUIRE(m["state"] != "failed");
            if (m["state"] == state) return i;
        }
        page.sendCamera(30, 20, 0.5, ++seq); // the same camera: keeps frames coming
        page.frameOf(seq);
    }
}

std::string joined(const Json& words) {
    std::string text;
    for (const auto& w : words) text += (text.empty() ? "" : " ") + w.get<std::string>();
    return text;
}

double meanDifference(const yv::RgbImage& a, const yv::RgbImage& b) {
    REQUIRE(a.pixels.size() == b.pixels.size());
    double sum = 0.0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) sum += std::abs(int(a.pixels[i]) - int(b.pixels[i]));
    return sum / double(a.pixels.size());
}

} // namespace

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

// `yarnvox view` end to end without a browser: the server run in-process on
// a small generated garment (llvmpipe), a WebSocket client speaking the
// protocol (served_view.h), JPEG frames decoded and compared for different
// cameras; a garbage message is refused, logged, and the page and the server
// go on. And the command's refusals before serving, and its stop on SIGTERM.
#include "core/error.h"
#include "served_view.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <future>
#include <mutex>
#include <thread>

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

using yv::test::Page;
using yv::test::ServedView;
using yv::test::meanDifference;

/// Pixels brighter than black in `image`'s columns [x0, x1).
int litPixels(const yv::RgbImage& image, int x0, int x1) {
    int lit = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = x0; x < x1; ++x) lit += image.at(x, y)[0] + image.at(x, y)[1] + image.at(x, y)[2] > 48;
    return lit;
}

} // namespace

TEST_CASE("View: frames arrive as JPEG over the WebSocket, follow the camera, and a garbage message is refused and logged",
          "[view][gl]") {
    YV_REQUIRE_GL();
    ServedView view;
    const int port = view.port.get_future().get();
    Page page(port);
    CHECK(page.hello["type"] == "hello");
    CHECK(page.hello["sideBySide"] == true);
    CHECK(page.hello["modes"][0] == "raycast");
    CHECK(page.hello["activeVoxels"].get<std::uint64_t>() > 0);

    // The first frame, at the --size given: slices on the left, the ray cast on the right.
    page.sendCamera(30, 1);
    const auto [firstStats, first] = page.frameOf(1);
    CHECK(first.width == 192);
    CHECK(first.height == 96);
    CHECK(firstStats["slices"].get<std::uint64_t>() > 0);
    CHECK(litPixels(first, 0, 96) > 100);
    CHECK(litPixels(first, 96, 192) > 100);

    // The ruler's measure: a pixel's width at the point looked at, in the
    // garment's units, and half as wide from half as far.
    CHECK(firstStats["pixelUnits"] == "world");
    const double pixel = firstStats["pixelSize"].get<double>();
    CHECK(pixel > 0.0);
    CHECK(pixel < page.hello["voxelSize"].get<double>() * 2.0);
    page.sendCamera(30, 20, 1.5, 100);
    CHECK(page.frameOf(100).first["pixelSize"].get<double>() == Approx(pixel / 2.0).epsilon(1e-9));

    const yv::RgbImage& a = first;
    page.sendCamera(120, 2);
    const yv::RgbImage b = page.frameOf(2).second;
    page.sendCamera(30, 3);
    const yv::RgbImage again = page.frameOf(3).second;
    CHECK(meanDifference(a, b) > 2.0);      // another camera, another picture
    CHECK(meanDifference(a, again) < 0.5); // the same camera, the same picture (the render is deterministic)

    // A size message changes the frame's size.
    page.send(R"({"type":"size","width":128,"height":64})");
    page.sendCamera(30, 4);
    CHECK(page.frameOf(4).second.width == 128);

    // Garbage: refused, logged in one line, and the page still gets frames.
    page.send("{{{ not json");
    page.send(R"({"type":"mode","mode":"no-such-mode"})");
    page.sendCamera(60, 5);
    const auto [stats5, picture5] = page.frameOf(5);
    CHECK(picture5.width == 128);
    REQUIRE(page.notices.size() >= 2);
    CHECK(page.notices[0].find("not JSON") != std::string::npos);
    CHECK(page.notices[1].find("no mode 'no-such-mode'") != std::string::npos);
    CHECK(view.logged("refused a message from 127.0.0.1:"));
    CHECK(view.logged("not JSON"));

    // Blended (the paper's Figure 3): one picture over the whole width, unlike the halves side by side.
    page.sendCamera(60, 40);
    const yv::RgbImage sideBySide = page.frameOf(40).second;
    page.send(R"({"type":"layout","blend":true})");
    page.sendCamera(60, 41);
    const auto [blendStats, blended] = page.frameOf(41);
    CHECK(blendStats["blend"] == true);
    CHECK(meanDifference(sideBySide, blended) > 2.0);
    // The garment in the middle of the one picture, where side by side the halves meet.
    CHECK(litPixels(blended, 54, 74) > 4 * litPixels(sideBySide, 54, 74) / 3);
    page.send(R"({"type":"layout","blend":false})");
    page.sendCamera(60, 42);
    CHECK(meanDifference(sideBySide, page.frameOf(42).second) < 0.5);

    // A screenshot larger than the frames: its own message and picture, at the size asked, of the same view.
    page.send(R"({"type":"screenshot","width":1536,"height":768})");
    page.sendCamera(60, 50);
    bool shot = false;
    for (int i = 0; i < 4 && !shot; ++i) {
        const yv::test::PageMessage message = page.read();
        if (!message.text) continue;
        const Json m = Json::parse(message.bytes);
        if (m["type"] != "screenshot") continue;
        const yv::test::PageMessage picture = page.read();
        REQUIRE(!picture.text);
        const yv::RgbImage big = yv::decodeJpeg(std::vector<std::uint8_t>(picture.bytes.begin(), picture.bytes.end()));
        CHECK(big.width == 1536);
        CHECK(big.height == 768);
        CHECK(litPixels(big, 0, 768) > 100 * 64);
        shot = true;
    }
    CHECK(shot);
    page.frameOf(50);

    // Saving before anything was voxelized in view is refused in one line, and changes nothing.
    page.send(R"({"type":"save-view"})");
    page.sendCamera(60, 6);
    page.frameOf(6);
    CHECK(page.notices.back().find("nothing to save yet") != std::string::npos);

    // A binary message and one over the size limit: the second closes that page, not the server.
    Page other(port);
    other.sendCamera(0, 1);
    other.frameOf(1);
    other.sendBinary(std::string("\x01\x02", 2));
    other.send(std::string(4096, ' '));
    page.sendCamera(90, 7);
    CHECK(page.frameOf(7).second.width == 128);
    CHECK(view.logged("a binary message"));
    CHECK(view.logged("over 1024 bytes"));
    CHECK(!view.failure);
}

TEST_CASE("View: the slices are drawn with the primitive asked for (auto: points on llvmpipe, tiles on a GPU)", "[view][gl]") {
    YV_REQUIRE_GL();
    for (const auto& [asked, drawn] : {std::pair{yv::SlicePrimitive::Auto, "points"}, std::pair{yv::SlicePrimitive::Boxes, "boxes"},
                                       std::pair{yv::SlicePrimitive::Tiles, "tiles"}}) {
        ServedView view(false, [asked](yv::ViewRequest& r) { r.quality.slicePrimitive = asked; });
        Page page(view.port.get_future().get());
        page.sendCamera(30, 1);
        const Json stats = page.frameOf(1).first;
        INFO(stats.dump());
        const bool llvmpipe = page.hello["renderer"].get<std::string>().find("llvmpipe") != std::string::npos;
        CHECK(stats["slicePrimitive"] == (asked == yv::SlicePrimitive::Auto && !llvmpipe ? "tiles" : drawn));
        CHECK(stats["slices"].get<std::uint64_t>() > 0);
        CHECK(view.failure == nullptr);
    }
}

TEST_CASE("View: a .vdb is ray cast full width, and every mode it offers draws a frame", "[view][gl]") {
    YV_REQUIRE_GL();
    ServedView view(true);
    Page page(view.port.get_future().get());
    CHECK(page.hello["sideBySide"] == false);
    const std::vector<std::string> modes = page.hello["modes"];
    INFO(page.hello.dump());
    // The .vdb records its garment, which is still there: the slices are one key away too.
    for (const char* expected : {"raycast", "mip", "texture-slicing", "half-angle", "splatting", "orientation", "slices"})
        CHECK(std::find(modes.begin(), modes.end(), expected) != modes.end());
    std::uint64_t seq = 0;
    yv::RgbImage raycast;
    for (const std::string& mode : modes) {
        page.send(Json{{"type", "mode"}, {"mode", mode}}.dump());
        page.sendCamera(30, ++seq);
        const auto [stats, picture] = page.frameOf(seq);
        INFO(mode);
        CHECK(stats["mode"] == mode);
        CHECK(picture.width == 192);
        // The garment fills the middle of the frame in every mode; the corners stay background.
        CHECK(litPixels(picture, 72, 120) > 200);
        CHECK(litPixels(picture, 0, 8) == 0);
        if (mode == "raycast") raycast = picture;
        else CHECK(meanDifference(raycast, picture) > 0.5); // each mode is a picture of its own
    }
    CHECK(page.notices.empty());
    // Its run's garment is found: its place in the world is known, and the ruler measures in the garment's units.
    page.sendCamera(30, ++seq);
    CHECK(page.frameOf(seq).first["pixelUnits"] == "world");
    CHECK(page.hello["voxelSize"].is_number());
}

TEST_CASE("View: the page is served over HTTP on the same port", "[view][gl]") {
    YV_REQUIRE_GL();
    ServedView view;
    const int port = view.port.get_future().get();
    const std::vector<std::string> targets = {"/", "/view.js", "/nothing"};
    const std::vector<yv::test::HttpReply> replies = yv::test::httpGet(port, targets);
    REQUIRE(replies.size() == targets.size());
    for (std::size_t i = 0; i < targets.size(); ++i) {
        const std::string& target = targets[i];
        INFO(target);
        if (target == "/nothing") {
            CHECK(replies[i].status == 404);
        } else {
            CHECK(replies[i].status == 200);
            CHECK(replies[i].body.find(target == "/" ? "<script src=\"view.js\">" : "new WebSocket(") != std::string::npos);
        }
    }
}

TEST_CASE("yarnvox view refuses a port in use, a missing file and a bad option in one line, before serving", "[view][cli]") {
    yv::test::ScratchDir scratch("yv_view_cli");
    const fs::path bcc = scratch.path / "plain.bcc";
    REQUIRE(yv::test::runYarnvox("gen --pattern plain --crossings 4 --quiet -o " + bcc.string()).exitCode == 0);
    yv::ViewServerOptions taken;
    taken.port = 0;
    const yv::ViewServer holder(taken, [](const std::string&) {});
    const std::string port = std::to_string(holder.port());

    const auto inUse = yv::test::runYarnvox("view " + bcc.string() + " --port " + port);
    CHECK(inUse.exitCode == 1);
    CHECK(inUse.output == "yarnvox: error: 127.0.0.1 port " + port + " is in use: give another with --port (0: any free port)\n");
    const auto missing = yv::test::runYarnvox("view " + (scratch.path / "none.vdb").string() + " --port 0");
    CHECK(missing.exitCode == 1);
    CHECK(missing.output.find("none.vdb: no such file or directory") != std::string::npos);
    CHECK(std::count(missing.output.begin(), missing.output.end(), '\n') == 1);
    const auto size = yv::test::runYarnvox("view " + bcc.string() + " --port 0 --size 8x8");
    CHECK(size.exitCode == 1);
    CHECK(size.output.find("--size '8x8'") != std::string::npos);
    const auto beside = yv::test::runYarnvox("view " + bcc.string() + " --port 0 --beside " + (scratch.path / "gone.vdb").string());
    CHECK(beside.exitCode == 1);
    CHECK(beside.output.find("--beside " + (scratch.path / "gone.vdb").string() + ": no such file or directory") != std::string::npos);
    CHECK(std::count(beside.output.begin(), beside.output.end(), '\n') == 1);
    const auto bind = yv::test::runYarnvox("view " + bcc.string() + " --bind localhost-ish --port 0");
    CHECK(bind.exitCode == 1);
    CHECK(bind.output.find("--bind 'localhost-ish': not an IP address") != std::string::npos);
    const auto primitive = yv::test::runYarnvox("view " + bcc.string() + " --port 0 --slice-primitive quads");
    CHECK(primitive.exitCode == 1);
    CHECK(primitive.output == "yarnvox: error: --slice-primitive 'quads': expected auto, tiles, points or boxes\n");
}

TEST_CASE("yarnvox view says its address and the ssh -L line, and stops cleanly on SIGTERM", "[view][cli][gl]") {
    YV_REQUIRE_GL();
    yv::test::ScratchDir scratch("yv_view_stop");
    const fs::path bcc = scratch.path / "plain.bcc";
    REQUIRE(yv::test::runYarnvox("gen --pattern plain --crossings 4 --quiet -o " + bcc.string()).exitCode == 0);
    const fs::path out = scratch.path / "out.txt";
    // Started in the background; SIGTERM once the address is printed (at most 120 s).
    const auto run = yv::test::runShell(
        std::string(YV_BINARY_DIR) + "/yarnvox view " + bcc.string() + " --port 0 --resolution 32 > " + out.string() +
        " 2>&1 & pid=$!; for i in $(seq 1200); do grep -q 'http://' " + out.string() +
        " && break; sleep 0.1; done; kill -TERM $pid; wait $pid; echo \"exit $?\"; cat " + out.string());
    INFO(run.output);
    CHECK(run.output.find("exit 0") != std::string::npos);
    CHECK(run.output.find("at http://127.0.0.1:") != std::string::npos);
    CHECK(run.output.find("ssh -L ") != std::string::npos);
    CHECK(run.output.find("yarnvox view: stopped by SIGTERM") != std::string::npos);
}

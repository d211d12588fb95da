// Frames while the camera moves (issue: "coarser levels and fewer slices
// where a frame would be late, full quality as soon as it stops, and a
// switch that never degrades"), in-process on a garment's view: a moving
// frame late for the slices' time draws the next at a coarser level of
// detail (fewer slabs) and every moving frame is a JPEG of less quality,
// the camera stopped draws at the level and quality asked for again, and a
// page that turned degrading off gets full quality throughout.
#include "served_view.h"

#include <catch2/catch.hpp>

#include <cstdint>

using Json = nlohmann::json;
using yv::test::Page;
using yv::test::ServedView;

namespace {

struct Seen {
    double lod = -1.0;
    std::uint64_t slices = 0;
    bool degraded = false;
    int quality = 0; ///< the frame's JPEG quality
};

Seen frameAt(Page& page, double azimuth, bool moving, std::uint64_t& seq) {
    page.sendCamera(azimuth, 20, 1.2, ++seq, moving);
    const Json stats = page.frameOf(seq).first;
    REQUIRE(stats["sliceLod"].is_number());
    CHECK(stats["moving"] == moving);
    return {stats["sliceLod"].get<double>(), stats["slices"].get<std::uint64_t>(), stats["degraded"].get<bool>(),
            stats["quality"].get<int>()};
}

} // namespace

TEST_CASE("View: frames late while the camera moves draw fewer slices, a stopped camera draws them all again, and a page "
          "may turn degrading off",
          "[view][gl]") {
    YV_REQUIRE_GL();
    // Every moving frame counts as late (its slices may take no time at all):
    // what follows does not hang on how fast this machine draws.
    ServedView view(false, [](yv::ViewRequest& r) {
        r.quality.lodPixels = 1.0;
        r.quality.movingSeconds = 0.0;
        r.initial.width = 256;
        r.initial.height = 128;
    });
    Page page(view.port.get_future().get());
    std::uint64_t seq = 0;
    const Seen still = frameAt(page, 30, false, seq);
    CHECK(still.lod == 1.0);
    CHECK_FALSE(still.degraded);
    CHECK(still.quality == 85); // --quality's default
    REQUIRE(still.slices > 0);

    // Moving: each late frame doubles the next one's level of detail, up to 64 pixels.
    Seen moving = frameAt(page, 31, true, seq);
    CHECK(moving.lod == 1.0); // the first moving frame is drawn as asked; it was late, so...
    CHECK(moving.quality == 70); // fewer bytes while moving (--moving-quality's default)
    double lod = moving.lod;
    for (int i = 0; i < 8; ++i) {
        moving = frameAt(page, 32 + i, true, seq);
        CHECK(moving.lod == std::min(64.0, 2.0 * lod));
        CHECK(moving.degraded);
        lod = moving.lod;
    }
    CHECK(lod == 64.0);
    // ...and draws fewer slices than the camera stopped at the same place.
    const Seen coarse = frameAt(page, 45, true, seq);
    const Seen stoppedThere = frameAt(page, 45, false, seq);
    CHECK(coarse.slices < stoppedThere.slices);
    CHECK(stoppedThere.lod == 1.0);
    CHECK_FALSE(stoppedThere.degraded);
    CHECK(stoppedThere.quality == 85);

    // The switch: moving frames at full quality while degrading is off.
    page.send(R"({"type":"quality","degrade":false})");
    for (int i = 0; i < 3; ++i) {
        const Seen full = frameAt(page, 46 + i, true, seq);
        CHECK(full.lod == 1.0);
        CHECK_FALSE(full.degraded);
        CHECK(full.quality == 85);
    }
    // On again: the coarse level reached before is where moving frames go on.
    page.send(R"({"type":"quality","degrade":true})");
    CHECK(frameAt(page, 50, true, seq).lod == 64.0);
    CHECK(view.failure == nullptr);
}

TEST_CASE("View: a moving camera's late frames draw the volume a level coarser, the stopped camera the budget's level",
          "[view][gl]") {
    YV_REQUIRE_GL();
    ServedView view(true, [](yv::ViewRequest& r) {
        r.quality.movingSeconds = 0.0; // every moving frame is late
        r.initial.width = 192;
        r.initial.height = 128;
    });
    Page page(view.port.get_future().get());
    std::uint64_t seq = 0;
    const auto frame = [&](double azimuth, bool moving) {
        page.sendCamera(azimuth, 20, 2.5, ++seq, moving);
        return page.frameOf(seq);
    };
    const auto [still, stillPicture] = frame(30, false);
    CHECK(still["level"] == 0);
    CHECK(still["coarserLevels"] == 0);
    // The first moving frame is drawn at the budget's level and was late; the next ones coarser, a level a frame, up to 3.
    CHECK(frame(31, true).first["coarserLevels"] == 0);
    int last = 0;
    for (int i = 0; i < 4; ++i) {
        const Json stats = frame(32 + i, true).first;
        INFO(stats.dump());
        CHECK(stats["coarserLevels"] == std::min(3, i + 1));
        CHECK(stats["degraded"] == true);
        CHECK(stats["level"].get<int>() > 0);
        CHECK(stats["level"].get<int>() >= last);
        last = stats["level"];
    }
    // A coarser level is a different picture of the same garment; stopped, the budget's level again, the same picture.
    const auto [coarse, coarsePicture] = frame(30, true);
    CHECK(coarse["level"].get<int>() > 0);
    const auto [stopped, stoppedPicture] = frame(30, false);
    CHECK(stopped["level"] == 0);
    CHECK(stopped["degraded"] == false);
    double difference = 0.0, again = 0.0;
    for (std::size_t i = 0; i < stillPicture.pixels.size(); ++i) {
        difference += std::abs(int(coarsePicture.pixels[i]) - int(stillPicture.pixels[i]));
        again += std::abs(int(stoppedPicture.pixels[i]) - int(stillPicture.pixels[i]));
    }
    CHECK(difference / double(stillPicture.pixels.size()) > 0.5);
    CHECK(again / double(stillPicture.pixels.size()) < 0.5);
    // Degrading off: moving frames at the budget's level.
    page.send(R"({"type":"quality","degrade":false})");
    CHECK(frame(40, true).first["level"] == 0);
    CHECK(!view.failure);
}

TEST_CASE("View: moving frames over --moving-mbit are drawn at half the size until the full size fits again, never "
          "the stopped camera's or with degrading off",
          "[view][gl]") {
    YV_REQUIRE_GL();
    // 2.16 Mbit/s at 30 frames a second: 9000 bytes a frame. The garment
    // close up at 512x256 takes more; far away, a half-size frame takes
    // under a quarter of 0.8 of it.
    ServedView view(false, [](yv::ViewRequest& r) {
        r.encoding.movingMbitPerSecond = 2.16;
        r.quality.movingSeconds = 1e3; // no slice level of detail in the way
        r.initial.width = 512;
        r.initial.height = 256;
    });
    Page page(view.port.get_future().get());
    std::uint64_t seq = 0;
    const auto frame = [&](double azimuth, double distance, bool moving) {
        page.sendCamera(azimuth, 20, distance, ++seq, moving);
        Json stats = page.frameOf(seq).first;
        INFO(stats.dump());
        CHECK(stats["bytes"].get<double>() > 0);
        return stats;
    };
    const Json still = frame(30, 1.2, false);
    CHECK(still["width"] == 512);
    REQUIRE(still["bytes"].get<double>() > 9000.0);

    // The first moving frame is full size and over the bytes: the next ones are half as wide and high.
    const Json first = frame(31, 1.2, true);
    CHECK(first["width"] == 512);
    CHECK(first["quality"] == 70);
    CHECK(first["bytes"].get<double>() > 9000.0);
    for (int i = 0; i < 3; ++i) {
        const Json half = frame(32 + i, 1.2, true);
        CHECK(half["width"] == 256);
        CHECK(half["height"] == 128);
        CHECK(half["degraded"] == true);
    }
    // Stopped: the page's size again, whatever the moving frames were.
    const Json stopped = frame(35, 1.2, false);
    CHECK(stopped["width"] == 512);
    CHECK(stopped["height"] == 256);
    CHECK(stopped["degraded"] == false);

    // Far away the garment is a few pixels: a half-size frame shows the full size fits, and the next is full size.
    const Json far = frame(36, 60, true);
    CHECK(far["width"] == 256);
    CHECK(4.0 * far["bytes"].get<double>() < 0.8 * 9000.0);
    CHECK(frame(37, 60, true)["width"] == 512);

    // Degrading off: moving frames at the page's size even where they take more.
    frame(38, 1.2, true); // over the bytes again
    page.send(R"({"type":"quality","degrade":false})");
    for (int i = 0; i < 2; ++i) CHECK(frame(39 + i, 1.2, true)["width"] == 512);
    CHECK(!view.failure);
}

// The live view's hub (src/view/view_hub.h) without GL: camera messages that
// arrive while a frame is drawn are coalesced (only the latest state is drawn
// next), a state already drawn is not drawn again, a mode the view lacks is
// refused, and pages are served in turn.
#include "core/error.h"
#include "view/view_hub.h"

#include <catch2/catch.hpp>

#include <chrono>
#include <condition_variable>
#include <future>
#include <mutex>
#include <thread>
#include <vector>

namespace {

/// Draws nothing: records the states asked for, and holds the first draw until released.
struct RecordingSource : yv::FrameSource {
    std::mutex mutex;
    std::condition_variable wake;
    std::vector<yv::ViewState> drawn;
    bool holdFirst = true, firstStarted = false;

    yv::Outgoing draw(const yv::ViewState& state) override {
        std::unique_lock lock(mutex);
        drawn.push_back(state);
        if (drawn.size() == 1) {
            firstStarted = true;
            wake.notify_all();
            wake.wait(lock, [&] { return !holdFirst; });
        }
        wake.notify_all();
        return yv::Outgoing{"stats", std::make_shared<const std::vector<std::uint8_t>>()};
    }
    yv::Outgoing voxelizeInView(const yv::ViewState&) override { throw yv::Error("nothing in view"); }
    yv::Outgoing saveView(bool) override { throw yv::Error("nothing to save"); }
    yv::Outgoing screenshot(const yv::ViewState&) override { throw yv::Error("no screenshots here"); }

    bool waitFor(const std::function<bool()>& done) {
        std::unique_lock lock(mutex);
        return wake.wait_for(lock, std::chrono::seconds(30), done);
    }
};

yv::CameraMessage camera(double azimuth, std::uint64_t seq) {
    yv::CameraMessage m;
    m.camera.azimuth = azimuth;
    m.camera.seq = seq;
    return m;
}

} // namespace

TEST_CASE("View hub: cameras that arrive during a frame are coalesced, the latest drawn once", "[view][hub]") {
    yv::ViewHub hub(yv::ViewControls{{"raycast", "mip"}, {"fibre", "heat"}, false}, yv::ViewState{});
    RecordingSource source;
    std::thread loop([&] { hub.run(source); });
    std::vector<std::string> delivered;
    std::mutex deliveredMutex;
    auto page = hub.join([&](yv::Outgoing out) {
        const std::lock_guard lock(deliveredMutex);
        delivered.push_back(out.text);
    });
    hub.apply(*page, camera(10, 1));
    REQUIRE(source.waitFor([&] { return source.firstStarted; }));
    // Ten cameras while the first frame is drawn: only the last is drawn next.
    for (int i = 2; i <= 11; ++i) hub.apply(*page, camera(10.0 * i, std::uint64_t(i)));
    {
        const std::lock_guard lock(source.mutex);
        source.holdFirst = false;
    }
    source.wake.notify_all();
    REQUIRE(source.waitFor([&] { return source.drawn.size() >= 2; }));
    // The same state again, and a refused mode: nothing more to draw.
    hub.apply(*page, camera(110, 11));
    CHECK_THROWS_WITH(hub.apply(*page, yv::ModeMessage{"slices"}), Catch::Contains("no mode 'slices'"));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    hub.stop();
    loop.join();
    REQUIRE(source.drawn.size() == 2);
    CHECK(source.drawn[0].camera.seq == 1);
    CHECK(source.drawn[1].camera.seq == 11);
    CHECK(source.drawn[1].camera.azimuth == 110.0);
    CHECK(delivered.size() == 2);
}

TEST_CASE("View hub: a new page is drawn once it asks, and pages are served in turn", "[view][hub]") {
    yv::ViewHub hub(yv::ViewControls{{"raycast", "mip"}, {"fibre", "heat"}, false}, yv::ViewState{});
    RecordingSource source;
    source.holdFirst = false;
    std::thread loop([&] { hub.run(source); });
    auto a = hub.join([](yv::Outgoing) {});
    auto b = hub.join([](yv::Outgoing) {});
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    {
        const std::lock_guard lock(source.mutex);
        CHECK(source.drawn.empty()); // joining alone draws nothing
    }
    hub.apply(*a, yv::ModeMessage{"mip"});
    hub.apply(*b, yv::SizeMessage{320, 200});
    REQUIRE(source.waitFor([&] { return source.drawn.size() >= 2; }));
    hub.leave(a);
    hub.apply(*a, camera(5, 3)); // a page that left is not drawn
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    hub.stop();
    loop.join();
    REQUIRE(source.drawn.size() == 2);
    const bool aFirst = source.drawn[0].mode == "mip";
    CHECK(source.drawn[aFirst ? 0 : 1].mode == "mip");
    CHECK(source.drawn[aFirst ? 1 : 0].width == 320);
}

TEST_CASE("View hub: a transfer function and twist change the state drawn, a preset or twist the view lacks is refused", "[view][hub]") {
    using Catch::Contains;
    yv::ViewState initial;
    initial.twist = 2.0;
    RecordingSource source;
    source.holdFirst = false;
    SECTION("a garment's view: both change what is drawn") {
        yv::ViewHub hub(yv::ViewControls{{"raycast"}, {"fibre", "heat"}, true}, initial);
        std::thread loop([&] { hub.run(source); });
        auto page = hub.join([](yv::Outgoing) {});
        hub.apply(*page, yv::TransferMessage{"heat", 4.0});
        hub.apply(*page, yv::TwistMessage{-1.5});
        REQUIRE(source.waitFor([&] {
            return !source.drawn.empty() && source.drawn.back().transfer == "heat" && source.drawn.back().twist == -1.5;
        }));
        CHECK(source.drawn.back().opacity == 4.0);
        CHECK_THROWS_WITH(hub.apply(*page, yv::TransferMessage{"rainbow", 1.0}), Contains("no transfer function 'rainbow'"));
        hub.stop();
        loop.join();
    }
    SECTION("a volume without its garment: the twist is refused, the state unchanged") {
        yv::ViewHub hub(yv::ViewControls{{"raycast"}, {"fibre"}, false}, initial);
        auto page = hub.join([](yv::Outgoing) {});
        CHECK_THROWS_WITH(hub.apply(*page, yv::TwistMessage{1.0}), Contains("view the .bcc"));
        std::thread loop([&] { hub.run(source); });
        hub.apply(*page, yv::ModeMessage{"raycast"});
        REQUIRE(source.waitFor([&] { return !source.drawn.empty(); }));
        CHECK(source.drawn.back().twist == 2.0);
        CHECK(source.drawn.back().transfer == "fibre");
        hub.stop();
        loop.join();
    }
}

// A `yarnvox view` served in-process for tests (a small generated garment or
// its .vdb, on llvmpipe), and a page's side of its protocol spoken with
// Beast: what the view's tests share.
#pragma once

#include "run_cli.h"
#include "test_helpers.h"
#include "view/jpeg_frame.h"
#include "view/view_run.h"

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <functional>
#include <future>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace yv::test {

namespace fs = std::filesystem;
namespace beast = boost::beast;
namespace net = boost::asio;
using tcp = net::ip::tcp;
using Json = nlohmann::json;

/// A view of a small garment served on a thread of the test, stopped and joined when it goes.
struct ServedView {
    yv::test::ScratchDir scratch{"yv_view"};
    std::atomic<bool> stop{false};
    std::mutex logMutex;
    std::vector<std::string> log;
    std::promise<int> port;
    std::thread thread, watchdog;
    std::exception_ptr failure;
    std::mutex doneMutex;
    std::condition_variable doneWake;
    bool done = false;

    /// `asVdb`: the garment voxelized by `yarnvox voxelize` first and the .vdb viewed; else the garment.
    /// `adjust` changes the request before the view starts.
    explicit ServedView(bool asVdb = false, const std::function<void(yv::ViewRequest&)>& adjust = {}) {
        const fs::path bcc = scratch.path / "plain.bcc";
        REQUIRE(yv::test::runYarnvox("gen --pattern plain --crossings 16 --quiet -o " + bcc.string()).exitCode == 0);
        const fs::path vdb = scratch.path / "plain.vdb";
        if (asVdb)
            REQUIRE(yv::test::runYarnvox("voxelize " + bcc.string() + " --resolution 48 --quiet -o " + vdb.string()).exitCode == 0);
        yv::ViewRequest request;
        request.input = asVdb ? vdb.string() : bcc.string();
        request.server.port = 0;
        request.initial.width = 192;
        request.initial.height = 96;
        request.voxelize.resolution = 48;
        request.saveDir = scratch.path.string();
        if (adjust) adjust(request);
        // A frame that never comes must fail the test, not hang it: after 300 s the
        // server stops, which closes the pages and ends their blocking reads.
        watchdog = std::thread([this] {
            std::unique_lock lock(doneMutex);
            if (!doneWake.wait_for(lock, std::chrono::seconds(300), [this] { return done; })) stop = true;
        });
        thread = std::thread([this, request] {
            try {
                yv::runView(
                    request, [this](int p) { port.set_value(p); }, [this] { return stop.load(); },
                    [this](const std::string& line) {
                        const std::lock_guard lock(logMutex);
                        log.push_back(line);
                    });
            } catch (...) {
                failure = std::current_exception();
                try {
                    port.set_exception(std::current_exception());
                } catch (...) {
                }
            }
        });
    }
    ~ServedView() {
        {
            const std::lock_guard lock(doneMutex);
            done = true;
        }
        doneWake.notify_all();
        watchdog.join();
        stop = true;
        thread.join();
    }
    bool logged(const std::string& part) {
        const std::lock_guard lock(logMutex);
        for (const std::string& line : log)
            if (line.find(part) != std::string::npos) return true;
        return false;
    }
};

/// A page's side of the protocol, synchronous (ServedView's watchdog ends a read that waits too long).
struct Page {
    net::io_context io;
    beast::websocket::stream<tcp::socket> ws{io};
    Json hello;
    std::vector<std::string> notices;
    std::vector<Json> voxelizeMessages; ///< {"type":"voxelize"} messages, in order

    explicit Page(int port) {
        tcp::resolver resolver(io);
        net::connect(ws.next_layer(), resolver.resolve("127.0.0.1", std::to_string(port)));
        ws.next_layer().set_option(tcp::no_delay(true));
        ws.handshake("127.0.0.1", "/ws");
        hello = Json::parse(readText());
    }
    std::string readText() {
        beast::flat_buffer b;
        ws.read(b);
        REQUIRE(ws.got_text());
        return beast::buffers_to_string(b.data());
    }
    void send(const std::string& text) {
        ws.text(true);
        ws.write(net::buffer(text));
    }
    void sendCamera(double azimuth, std::uint64_t seq) {
        sendCamera(azimuth, 20, 3, seq);
    }
    void sendCamera(double azimuth, double elevation, double distance, std::uint64_t seq, bool moving = false) {
        send(Json{{"type", "camera"}, {"azimuth", azimuth}, {"elevation", elevation}, {"distance", distance},
                  {"panX", 0}, {"panY", 0}, {"seq", seq}, {"moving", moving}}.dump());
    }
    /// The next frame: its stats and its picture (notices on the way are kept).
    std::pair<Json, yv::RgbImage> readFrame() {
        Json stats;
        for (;;) {
            beast::flat_buffer b;
            ws.read(b);
            if (ws.got_text()) {
                const Json m = Json::parse(beast::buffers_to_string(b.data()));
                if (m["type"] == "stats") stats = m;
                if (m["type"] == "notice") notices.push_back(m["text"]);
                if (m["type"] == "voxelize") voxelizeMessages.push_back(m);
                continue;
            }
            const auto* p = static_cast<const std::uint8_t*>(b.data().data());
            REQUIRE(stats.is_object());
            CHECK(stats["bytes"] == b.size());
            return {stats, yv::decodeJpeg(std::vector<std::uint8_t>(p, p + b.size()))};
        }
    }
    /// Frames until the one showing camera `seq`.
    std::pair<Json, yv::RgbImage> frameOf(std::uint64_t seq) {
        for (;;) {
            auto frame = readFrame();
            if (frame.first["seq"] == seq) return frame;
        }
    }
};

/// Reads frames until a voxelize message in `state` has arrived at index
/// `from` or later, and returns its index (or the view's watchdog ends the
/// wait); a failed run fails the test. The answer to a request and the
/// worker's "running" may come in either order.
inline std::size_t waitForVoxelize(Page& page, const std::string& state, std::uint64_t& seq, std::size_t from) {
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

/// A command the view gives (its words) as one line.
inline std::string joined(const Json& words) {
    std::string text;
    for (const auto& w : words) text += (text.empty() ? "" : " ") + w.get<std::string>();
    return text;
}

/// The mean absolute difference of two pictures' bytes.
inline double meanDifference(const yv::RgbImage& a, const yv::RgbImage& b) {
    REQUIRE(a.pixels.size() == b.pixels.size());
    double sum = 0.0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) sum += std::abs(int(a.pixels[i]) - int(b.pixels[i]));
    return sum / double(a.pixels.size());
}

} // namespace yv::test

// A `yarnvox view` served in-process for tests (a small generated garment or
// its .vdb, on llvmpipe), and a page's side of its protocol: what the view's
// tests share. Beast stays in served_view.cpp, compiled once, not in every
// test that speaks to a view.
#pragma once

#include "run_cli.h"
#include "test_helpers.h"
#include "view/jpeg_frame.h"
#include "view/view_run.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace yv::test {

namespace fs = std::filesystem;
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
    explicit ServedView(bool asVdb = false, const std::function<void(yv::ViewRequest&)>& adjust = {});
    ~ServedView();
    bool logged(const std::string& part);
};

/// One WebSocket message as it came: text (JSON) or binary (a picture).
struct PageMessage {
    bool text = false;
    std::string bytes;
};

/// A page's side of the protocol, synchronous (ServedView's watchdog ends a read that waits too long).
struct Page {
    Json hello;
    std::vector<std::string> notices;
    std::vector<Json> voxelizeMessages; ///< {"type":"voxelize"} messages, in order

    explicit Page(int port);
    ~Page();
    PageMessage read();
    std::string readText();
    void send(const std::string& text);
    void sendBinary(const std::string& bytes);
    void sendCamera(double azimuth, std::uint64_t seq) { sendCamera(azimuth, 20, 3, seq); }
    void sendCamera(double azimuth, double elevation, double distance, std::uint64_t seq, bool moving = false);
    /// The next frame: its stats and its picture (notices on the way are kept).
    std::pair<Json, yv::RgbImage> readFrame();
    /// Frames until the one showing camera `seq`.
    std::pair<Json, yv::RgbImage> frameOf(std::uint64_t seq);

  private:
    struct Socket;
    std::unique_ptr<Socket> socket;
};

/// An HTTP GET's answer: status code and body.
struct HttpReply {
    int status = 0;
    std::string body;
};

/// GETs each target in turn over one connection to the view on `port`.
std::vector<HttpReply> httpGet(int port, const std::vector<std::string>& targets);

/// Reads frames until a voxelize message in `state` has arrived at index
/// `from` or later, and returns its index (or the view's watchdog ends the
/// wait); a failed run fails the test. The answer to a request and the
/// worker's "running" may come in either order.
std::size_t waitForVoxelize(Page& page, const std::string& state, std::uint64_t& seq, std::size_t from);

/// A command the view gives (its words) as one line.
std::string joined(const Json& words);

/// The mean absolute difference of two pictures' bytes.
double meanDifference(const yv::RgbImage& a, const yv::RgbImage& b);

} // namespace yv::test

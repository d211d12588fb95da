// yv_view_bench: drives a running `yarnvox view` through its WebSocket
// protocol along a scripted camera path (a first frame on a line of its
// own, an orbit, a close-up pan, a zoom out, then stops that each voxelize
// what the camera sees, for a garment's view) and prints one JSON line a phase: input-to-picture latency (a camera
// message sent to its frame received, one at a time), the server's render
// and encode times, frame intervals, bytes a frame, the JPEG quality and
// how many frames came smaller than asked (--moving-mbit), and (given the
// view's process id, on the same machine) the CPU time the view's process
// took a frame. The view and the benchmark may run on different machines;
// the numbers include the network.
//   build/yarnvox view garment.vdb --port 8080 &
//   build/bench/yv_view_bench --port 8080 --size 1280x720 --frames 120 --mode raycast
#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <stdexcept>
#include <cstring>
#include <string>
#include <unistd.h>
#include <vector>

namespace beast = boost::beast;
namespace net = boost::asio;
using tcp = net::ip::tcp;
using Json = nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

struct Options {
    std::string host = "127.0.0.1", mode = "raycast";
    int port = 8080, width = 1280, height = 720, frames = 120, stops = 5;
    int serverPid = 0; ///< the view's process, for its CPU time (0: not measured)
    /// The phases' cameras say they are moving, as a page's do while input goes on
    /// (the view may then draw fewer slices where a frame is late); --moving 0: not.
    bool moving = true;
};

/// The CPU seconds (user and system, all threads) process `pid` has used,
/// from /proc/PID/stat; negative where it cannot be read.
double processCpuSeconds(int pid) {
    if (pid <= 0) return -1.0;
    std::FILE* f = std::fopen(("/proc/" + std::to_string(pid) + "/stat").c_str(), "r");
    if (!f) return -1.0;
    char text[4096];
    const std::size_t n = std::fread(text, 1, sizeof text - 1, f);
    std::fclose(f);
    text[n] = 0;
    // The command name (field 2) is in parentheses and may hold spaces: count fields after its last ')'.
    const char* p = std::strrchr(text, ')');
    if (!p) return -1.0;
    unsigned long long utime = 0, stime = 0;
    // Fields 3 to 13 skipped; 14 utime, 15 stime, in clock ticks.
    if (std::sscanf(p + 2, "%*c %*d %*d %*d %*d %*d %*u %*u %*u %*u %*u %llu %llu", &utime, &stime) != 2) return -1.0;
    return double(utime + stime) / double(sysconf(_SC_CLK_TCK));
}

Json percentiles(std::vector<double> v) {
    if (v.empty()) return nullptr;
    std::sort(v.begin(), v.end());
    const auto at = [&](double p) { return v[std::min(v.size() - 1, std::size_t(p * double(v.size() - 1) + 0.5))]; };
    double sum = 0.0;
    for (double x : v) sum += x;
    return {{"p50", at(0.5)}, {"p95", at(0.95)}, {"p99", at(0.99)}, {"max", v.back()}, {"mean", sum / double(v.size())}};
}

struct Camera {
    double azimuth, elevation, distance, panX, panY;
};

class Session {
  public:
    explicit Session(const Options& o) : ws_(io_) {
        tcp::resolver resolver(io_);
        net::connect(ws_.next_layer(), resolver.resolve(o.host, std::to_string(o.port)));
        ws_.next_layer().set_option(tcp::no_delay(true));
        ws_.handshake(o.host, "/ws");
        hello_ = Json::parse(readText());
        send(Json{{"type", "size"}, {"width", o.width}, {"height", o.height}});
        send(Json{{"type", "mode"}, {"mode", o.mode}});
    }
    const Json& hello() const { return hello_; }

    /// The next message: a text one parsed (the stats of the frame to come
    /// kept), or a frame's JPEG (`frame` true, its size in `bytes`).
    struct Message {
        Json text;
        bool frame = false;
        std::size_t bytes = 0;
    };
    Message next() {
        beast::flat_buffer b;
        ws_.read(b);
        if (!ws_.got_text()) return {nullptr, true, b.size()};
        Message m{Json::parse(beast::buffers_to_string(b.data()))};
        if (m.text["type"] == "stats") stats_ = m.text;
        return m;
    }

    /// Sends `c` and waits for its frame; returns the stats with latencyMs and arrival added.
    Json frameOf(const Camera& c, bool moving = false) {
        ++seq_;
        const auto sent = Clock::now();
        send(Json{{"type", "camera"}, {"azimuth", c.azimuth}, {"elevation", c.elevation}, {"distance", c.distance},
                  {"panX", c.panX}, {"panY", c.panY}, {"seq", seq_}, {"moving", moving}});
        for (;;) {
            const Message m = next();
            if (!m.frame) {
                if (m.text["type"] == "notice") std::fprintf(stderr, "view: %s\n", m.text["text"].get<std::string>().c_str());
                continue;
            }
            if (stats_.value("seq", std::uint64_t(0)) != seq_) continue; // an earlier state's frame
            Json s = stats_;
            s["latencyMs"] = std::chrono::duration<double, std::milli>(Clock::now() - sent).count();
            s["receivedBytes"] = m.bytes;
            return s;
        }
    }

    /// Asks for what the camera sees to be voxelized and waits for the first
    /// frame that shows a run newer than `previous`: that frame's stats, with
    /// stopToDetailMs (request sent to its frame received) added; null when
    /// the view answers that the box in view is the one it ran last.
    Json voxelizeAndWait(std::uint64_t previous) {
        const auto sent = Clock::now();
        double firstMs = -1.0;
        send(Json{{"type", "voxelize-view"}});
        for (;;) {
            const Message m = next();
            if (!m.frame) {
                const Json& t = m.text;
                if (t["type"] == "notice") throw std::runtime_error("view: " + t["text"].get<std::string>());
                if (t["type"] == "voxelize" && t["state"] == "failed") throw std::runtime_error("view: voxelize " + t.dump());
                if (t["type"] == "voxelize" && t["state"] == "already")
                    return nullptr; // this camera's box was run last: nothing new to show
                continue;
            }
            const Json& d = stats_["detail"];
            if (!d.is_object() || d["shown"] != true || d["id"].get<std::uint64_t>() <= previous) continue;
            // A large view comes in two passes: the first picture of the run, then its final one.
            const double ms = std::chrono::duration<double, std::milli>(Clock::now() - sent).count();
            if (firstMs < 0.0) firstMs = ms;
            if (d.value("final", true) != true) continue;
            Json s = stats_;
            s["stopToDetailMs"] = ms;
            s["stopToFirstMs"] = firstMs;
            return s;
        }
    }

  private:
    std::string readText() {
        beast::flat_buffer b;
        ws_.read(b);
        return beast::buffers_to_string(b.data());
    }
    void send(const Json& m) {
        ws_.text(true);
        ws_.write(net::buffer(m.dump()));
    }

    net::io_context io_;
    beast::websocket::stream<tcp::socket> ws_;
    Json hello_, stats_;
    std::uint64_t seq_ = 0;
};

void runPhase(Session& s, const std::string& phase, int frames, const std::function<Camera(double)>& path,
              const Options& o) {
    std::vector<double> latency, render, encode, bytes, interval, slices, sliceLod, quality;
    int smaller = 0; // frames drawn at less than the asked size (--moving-mbit)
    auto last = Clock::now();
    const auto start = last;
    const double cpuBefore = processCpuSeconds(o.serverPid);
    for (int i = 0; i < frames; ++i) {
        const Json f = s.frameOf(path(frames > 1 ? double(i) / double(frames - 1) : 0.0), o.moving);
        const auto now = Clock::now();
        if (i > 0) interval.push_back(std::chrono::duration<double, std::milli>(now - last).count());
        last = now;
        latency.push_back(f["latencyMs"]);
        render.push_back(f["renderMs"]);
        encode.push_back(f["encodeMs"]);
        bytes.push_back(f["receivedBytes"]);
        slices.push_back(f.value("slices", 0.0));
        if (f["sliceLod"].is_number()) sliceLod.push_back(f["sliceLod"]);
        if (f["quality"].is_number()) quality.push_back(f["quality"]);
        smaller += f.value("width", o.width) < o.width;
    }
    double meanBytes = 0.0;
    for (double b : bytes) meanBytes += b / double(bytes.size());
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    const double cpuAfter = processCpuSeconds(o.serverPid);
    // The view's CPU a frame, and what it would be at 60 frames a second (a core is 1.0).
    Json serverCpu = nullptr;
    if (cpuBefore >= 0.0 && cpuAfter >= cpuBefore)
        serverCpu = {{"msPerFrame", 1e3 * (cpuAfter - cpuBefore) / frames},
                     {"coresAtMeasuredRate", (cpuAfter - cpuBefore) / seconds},
                     {"coresAt60", 60.0 * (cpuAfter - cpuBefore) / frames}};
    const Json line = {{"phase", phase},
                       {"mode", o.mode},
                       {"input", s.hello()["name"]},
                       {"renderer", s.hello()["renderer"]},
                       {"activeVoxels", s.hello()["activeVoxels"]},
                       {"width", o.width},
                       {"height", o.height},
                       {"frames", frames},
                       {"framesPerSecond", double(frames) / seconds},
                       {"latencyMs", percentiles(latency)},
                       {"frameIntervalMs", percentiles(interval)},
                       {"renderMs", percentiles(render)},
                       {"encodeMs", percentiles(encode)},
                       {"bytes", percentiles(bytes)},
                       {"mbitPerSecondAt30", meanBytes * 8.0 * 30.0 / 1e6},
                       {"moving", o.moving},
                       {"slices", percentiles(slices)},
                       {"sliceLod", sliceLod.empty() ? Json() : percentiles(sliceLod)},
                       {"quality", quality.empty() ? Json() : percentiles(quality)},
                       {"smallerFrames", smaller},
                       {"serverCpu", serverCpu}};
    std::printf("%s\n", line.dump().c_str());
    std::fflush(stdout);
}

/// The view's first frame, on a line of its own: it makes the renderers and
/// loads what they draw (a garment's slices, a volume's bricks), which the
/// phases after it, the orbit first, should not count in their CPU and latency.
void runFirstFrame(Session& s, const Camera& camera, const Options& o) {
    const double cpuBefore = processCpuSeconds(o.serverPid);
    const Json f = s.frameOf(camera, o.moving);
    const double cpuAfter = processCpuSeconds(o.serverPid);
    const Json line = {{"phase", "first-frame"},
                       {"mode", o.mode},
                       {"input", s.hello()["name"]},
                       {"renderer", s.hello()["renderer"]},
                       {"width", o.width},
                       {"height", o.height},
                       {"latencyMs", f["latencyMs"]},
                       {"renderMs", f["renderMs"]},
                       {"serverCpuSeconds", cpuBefore >= 0.0 && cpuAfter >= cpuBefore ? Json(cpuAfter - cpuBefore) : Json()}};
    std::printf("%s\n", line.dump().c_str());
    std::fflush(stdout);
}

/// Stops at `stops` close-up cameras around the garment, each voxelized in view:
/// from the request (the page sends it when the camera stops) to its picture.
void runStopPhase(Session& s, int stops, const Options& o) {
    std::vector<double> stopToDetail, stopToFirst, runSeconds, active;
    std::uint64_t last = 0;
    int already = 0;
    Json runs = Json::array();
    for (int i = 0; i < stops; ++i) {
        s.frameOf(Camera{40.0 + 360.0 * i / stops, 15.0, 0.7, 0.0, 0.0});
        const Json f = s.voxelizeAndWait(last);
        if (f.is_null()) {
            ++already;
            continue;
        }
        const Json& d = f["detail"];
        last = d["id"];
        stopToDetail.push_back(f["stopToDetailMs"]);
        stopToFirst.push_back(f["stopToFirstMs"]);
        runSeconds.push_back(d["seconds"]);
        active.push_back(d["activeVoxels"]);
        // Where the time went: the run (request to .vdb written), then the
        // frame that opens it (openMs), loads its atlas (atlasMs) and makes
        // its renderer (rendererMs), all within renderMs, then encoding and sending.
        runs.push_back({{"voxelSize", d["voxelSize"]}, {"bboxWorld", d["bboxWorld"]}, {"activeVoxels", d["activeVoxels"]},
                        {"stopToDetailMs", f["stopToDetailMs"]}, {"stopToFirstMs", f["stopToFirstMs"]},
                        {"runSeconds", d["seconds"]},
                        {"frameRenderMs", f["renderMs"]}, {"frameEncodeMs", f["encodeMs"]},
                        {"frameOpenMs", f.value("openMs", 0.0)}, {"frameAtlasMs", f.value("atlasMs", 0.0)},
                        {"frameRendererMs", f.value("rendererMs", 0.0)}});
    }
    const Json line = {{"phase", "stop-and-voxelize"},
                       {"mode", o.mode},
                       {"input", s.hello()["name"]},
                       {"renderer", s.hello()["renderer"]},
                       {"width", o.width},
                       {"height", o.height},
                       {"stops", stops},
                       {"stopsAlreadyRun", already},
                       {"stopToDetailMs", percentiles(stopToDetail)},
                       {"stopToFirstPictureMs", percentiles(stopToFirst)},
                       {"runSeconds", percentiles(runSeconds)},
                       {"activeVoxels", percentiles(active)},
                       {"runs", runs}};
    std::printf("%s\n", line.dump().c_str());
    std::fflush(stdout);
}

int usage(const char* why) {
    std::fprintf(stderr, "yv_view_bench: %s\nusage: yv_view_bench [--host H] [--port P] [--size WxH] [--frames N] [--mode M] [--stops K] [--server-pid PID] [--moving 0|1]\n", why);
    return 2;
}

} // namespace

int main(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (i + 1 >= argc) return usage(("a value after " + a).c_str());
        const std::string v = argv[++i];
        if (a == "--host") o.host = v;
        else if (a == "--port") o.port = std::atoi(v.c_str());
        else if (a == "--frames") o.frames = std::atoi(v.c_str());
        else if (a == "--mode") o.mode = v;
        else if (a == "--stops") o.stops = std::atoi(v.c_str());
        else if (a == "--server-pid") o.serverPid = std::atoi(v.c_str());
        else if (a == "--moving") o.moving = v != "0";
        else if (a == "--size") {
            if (std::sscanf(v.c_str(), "%dx%d", &o.width, &o.height) != 2) return usage("--size WIDTHxHEIGHT");
        } else return usage(("an unknown option " + a).c_str());
    }
    if (o.frames < 2 || o.port <= 0) return usage("--frames at least 2, --port above 0");
    try {
        Session s(o);
        // A full turn around the garment at the default distance, after the first frame.
        const auto orbit = [](double t) { return Camera{30.0 + 360.0 * t, 20.0, 4.0, 0.0, 0.0}; };
        runFirstFrame(s, orbit(0.0), o);
        runPhase(s, "orbit", o.frames, orbit, o);
        // Close up, panning across the surface (the worst case for the slices: every slice still drawn).
        runPhase(s, "close-up", o.frames, [](double t) { return Camera{60.0, 10.0, 0.6, -0.5 + t, 0.2 * std::sin(6.0 * t)}; }, o);
        // Zooming back out from the close-up.
        runPhase(s, "zoom-out", o.frames / 2, [](double t) { return Camera{60.0, 10.0 + 20.0 * t, 0.6 + 3.4 * t, 0.5 * (1.0 - t), 0.0}; }, o);
        // A garment's view (its hello gives a voxel size): stop and voxelize what the camera sees.
        if (s.hello()["voxelSize"].is_number()) runStopPhase(s, o.stops, o);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "yv_view_bench: %s\n", e.what());
        return 1;
    }
    return 0;
}

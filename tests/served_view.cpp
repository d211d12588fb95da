#include "served_view.h"

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <algorithm>
#include <chrono>
#include <cstdlib>

namespace yv::test {

namespace beast = boost::beast;
namespace net = boost::asio;
using tcp = net::ip::tcp;

ServedView::ServedView(bool asVdb, const std::function<void(yv::ViewRequest&)>& adjust) {
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
    // A frame that never comes must fail the test, not hang it: after 300 s
    // (times YV_TEST_TIME_SCALE, which a sanitizer's run sets: ThreadSanitizer
    // runs the view several times slower) the server stops, which closes the
    // pages and ends their blocking reads.
    const char* scale = std::getenv("YV_TEST_TIME_SCALE");
    const double limit = 300.0 * (scale ? std::max(1.0, std::atof(scale)) : 1.0);
    watchdog = std::thread([this, limit] {
        std::unique_lock lock(doneMutex);
        if (!doneWake.wait_for(lock, std::chrono::duration<double>(limit), [this] { return done; })) stop = true;
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

ServedView::~ServedView() {
    {
        const std::lock_guard lock(doneMutex);
        done = true;
    }
    doneWake.notify_all();
    watchdog.join();
    stop = true;
    thread.join();
}

bool ServedView::logged(const std::string& part) {
    const std::lock_guard lock(logMutex);
    for (const std::string& line : log)
        if (line.find(part) != std::string::npos) return true;
    return false;
}

struct Page::Socket {
    net::io_context io;
    beast::websocket::stream<tcp::socket> ws{io};
};

Page::Page(int port) : socket(std::make_unique<Socket>()) {
    tcp::resolver resolver(socket->io);
    net::connect(socket->ws.next_layer(), resolver.resolve("127.0.0.1", std::to_string(port)));
    socket->ws.next_layer().set_option(tcp::no_delay(true));
    socket->ws.handshake("127.0.0.1", "/ws");
    hello = Json::parse(readText());
}

Page::~Page() = default;

PageMessage Page::read() {
    beast::flat_buffer b;
    socket->ws.read(b);
    return {socket->ws.got_text(), beast::buffers_to_string(b.data())};
}

std::string Page::readText() {
    PageMessage m = read();
    REQUIRE(m.text);
    return std::move(m.bytes);
}

void Page::send(const std::string& text) {
    socket->ws.text(true);
    socket->ws.write(net::buffer(text));
}

void Page::sendBinary(const std::string& bytes) {
    socket->ws.binary(true);
    socket->ws.write(net::buffer(bytes));
}

void Page::sendCamera(double azimuth, double elevation, double distance, std::uint64_t seq, bool moving) {
    send(Json{{"type", "camera"}, {"azimuth", azimuth}, {"elevation", elevation}, {"distance", distance},
              {"panX", 0}, {"panY", 0}, {"seq", seq}, {"moving", moving}}.dump());
}

std::pair<Json, yv::RgbImage> Page::readFrame() {
    Json stats;
    for (;;) {
        const PageMessage message = read();
        if (message.text) {
            const Json m = Json::parse(message.bytes);
            if (m["type"] == "stats") stats = m;
            if (m["type"] == "notice") notices.push_back(m["text"]);
            if (m["type"] == "voxelize") voxelizeMessages.push_back(m);
            continue;
        }
        REQUIRE(stats.is_object());
        CHECK(stats["bytes"] == message.bytes.size());
        return {stats, yv::decodeJpeg(std::vector<std::uint8_t>(message.bytes.begin(), message.bytes.end()))};
    }
}

std::pair<Json, yv::RgbImage> Page::frameOf(std::uint64_t seq) {
    for (;;) {
        auto frame = readFrame();
        if (frame.first["seq"] == seq) return frame;
    }
}

std::vector<HttpReply> httpGet(int port, const std::vector<std::string>& targets) {
    net::io_context io;
    beast::tcp_stream stream(io);
    tcp::resolver resolver(io);
    stream.connect(resolver.resolve("127.0.0.1", std::to_string(port)));
    std::vector<HttpReply> replies;
    for (const std::string& target : targets) {
        beast::http::request<beast::http::string_body> request(beast::http::verb::get, target, 11);
        request.set(beast::http::field::host, "127.0.0.1");
        beast::http::write(stream, request);
        beast::flat_buffer buffer;
        beast::http::response<beast::http::string_body> response;
        beast::http::read(stream, buffer, response);
        replies.push_back({int(response.result_int()), response.body()});
    }
    return replies;
}

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

} // namespace yv::test

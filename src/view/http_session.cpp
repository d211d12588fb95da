// One HTTP request a connection: GET / (the page), GET /view.js, or the
// WebSocket upgrade at /ws. Anything else is 404 or 405; a request larger
// than the page ever sends is refused by the parser's limits.
#include "view/page_files.h"
#include "view/view_sessions.h"

#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket/rfc6455.hpp>

#include <chrono>
#include <memory>
#include <optional>

namespace yv {
namespace {

namespace beast = boost::beast;
namespace http = beast::http;
using tcp = boost::asio::ip::tcp;

class HttpSession : public std::enable_shared_from_this<HttpSession> {
  public:
    HttpSession(tcp::socket socket, SessionShared& shared) : stream_(std::move(socket)), shared_(shared) {}

    void start() {
        parser_.emplace();
        parser_->header_limit(8 * 1024);
        parser_->body_limit(1024);
        stream_.expires_after(std::chrono::seconds(30));
        http::async_read(stream_, buffer_, *parser_,
                         [self = shared_from_this()](beast::error_code ec, std::size_t) { self->onRead(ec); });
    }

  private:
    void onRead(beast::error_code ec) {
        if (ec) return; // closed, timed out or malformed: the connection goes
        http::request<http::string_body> request = parser_->release();
        if (beast::websocket::is_upgrade(request)) {
            if (request.target() != "/ws") return reply(http::status::not_found, "text/plain", "no WebSocket here\n", request);
            stream_.expires_never();
            startWsSession(std::move(stream_), std::move(request), shared_);
            return;
        }
        if (request.method() != http::verb::get && request.method() != http::verb::head)
            return reply(http::status::method_not_allowed, "text/plain", "GET only\n", request);
        const beast::string_view target = request.target();
        // The camera and mode ride in the fragment (#...), which browsers do not send; a query is ignored.
        const beast::string_view path = target.substr(0, target.find('?'));
        if (path == "/" || path == "/index.html") return reply(http::status::ok, "text/html; charset=utf-8", pageFile("view.html"), request);
        if (path == "/view.js") return reply(http::status::ok, "text/javascript; charset=utf-8", pageFile("view.js"), request);
        reply(http::status::not_found, "text/plain", "not found\n", request);
    }

    void reply(http::status status, const char* type, const char* body, const http::request<http::string_body>& request) {
        auto response = std::make_shared<http::response<http::string_body>>(status, request.version());
        response->set(http::field::server, "yarnvox view");
        response->set(http::field::content_type, type);
        response->set(http::field::cache_control, "no-store");
        response->keep_alive(request.keep_alive());
        if (request.method() != http::verb::head) response->body() = body ? body : "";
        response->prepare_payload();
        http::async_write(stream_, *response, [self = shared_from_this(), response](beast::error_code ec, std::size_t) {
            if (!ec && response->keep_alive()) self->start();
            else self->stream_.socket().shutdown(tcp::socket::shutdown_send, ec);
        });
    }

    beast::tcp_stream stream_;
    beast::flat_buffer buffer_;
    std::optional<http::request_parser<http::string_body>> parser_;
    SessionShared& shared_;
};

} // namespace

int SessionShared::openPages() {
    std::erase_if(pages, [](const std::weak_ptr<WsSession>& p) { return p.expired(); });
    return int(pages.size());
}

void startHttpSession(tcp::socket socket, SessionShared& shared) {
    std::make_shared<HttpSession>(std::move(socket), shared)->start();
}

} // namespace yv

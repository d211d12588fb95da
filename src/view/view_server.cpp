#include "view/view_server.h"

#include "core/error.h"
#include "view/view_sessions.h"

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>

#include <chrono>

namespace yv {

namespace net = boost::asio;
using tcp = net::ip::tcp;

struct ViewServer::Impl {
    net::io_context io{1};
    tcp::acceptor acceptor{io};
    SessionShared shared;
    std::function<bool()> stopWanted;
    net::steady_timer watch{io};

    void accept() {
        acceptor.async_accept([this](boost::system::error_code ec, tcp::socket socket) {
            if (ec) {
                if (!acceptor.is_open()) return;
                shared.log(std::string("a connection could not be accepted: ") + ec.message());
            } else {
                // A frame is a text message and a binary one back to back: without this, Nagle's
                // algorithm holds the second until the page acknowledges the first (up to 40 ms).
                boost::system::error_code ignored;
                socket.set_option(tcp::no_delay(true), ignored);
                startHttpSession(std::move(socket), shared);
            }
            accept();
        });
    }

    void watchForStop() {
        watch.expires_after(std::chrono::milliseconds(100));
        watch.async_wait([this](boost::system::error_code) {
            if (!stopWanted()) return watchForStop();
            boost::system::error_code ignored;
            acceptor.close(ignored);
            for (const auto& page : shared.pages)
                if (auto p = page.lock()) closeWsSession(*p);
            // Whatever is still open after a second's closing handshakes goes with the io context.
            watch.expires_after(std::chrono::seconds(1));
            watch.async_wait([this](boost::system::error_code) { io.stop(); });
        });
    }
};

ViewServer::ViewServer(const ViewServerOptions& options, Log log) : impl_(std::make_unique<Impl>()) {
    impl_->shared.log = std::move(log);
    impl_->shared.maxPages = options.maxPages;
    boost::system::error_code ec;
    const net::ip::address address = net::ip::make_address(options.bind, ec);
    if (ec) throw Error("--bind '" + options.bind + "': not an IP address (e.g. 127.0.0.1, 0.0.0.0, ::1)");
    if (options.port < 0 || options.port > 65535)
        throw Error("--port " + std::to_string(options.port) + ": expected 0 to 65535 (0: any free port)");
    const tcp::endpoint endpoint(address, static_cast<unsigned short>(options.port));
    const std::string where = options.bind + " port " + std::to_string(options.port);
    impl_->acceptor.open(endpoint.protocol(), ec);
    if (!ec) impl_->acceptor.set_option(net::socket_base::reuse_address(true), ec);
    if (!ec) impl_->acceptor.bind(endpoint, ec);
    // Listening at once holds the port (a second server is refused now, not
    // later); connections wait in the backlog until serve() answers them.
    if (!ec) impl_->acceptor.listen(net::socket_base::max_listen_connections, ec);
    if (ec == net::error::address_in_use)
        throw Error(where + " is in use: give another with --port (0: any free port)");
    if (ec) throw Error("cannot listen on " + where + ": " + ec.message());
}

ViewServer::~ViewServer() = default;

int ViewServer::port() const { return impl_->acceptor.local_endpoint().port(); }

void ViewServer::serve(ViewHub& hub, const std::string& hello, const std::function<bool()>& stopWanted) {
    impl_->shared.hub = &hub;
    impl_->shared.hello = hello;
    impl_->stopWanted = stopWanted;
    impl_->accept();
    impl_->watchForStop();
    impl_->io.run();
}

} // namespace yv

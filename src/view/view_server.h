// The server of `yarnvox view`: one port, the page over HTTP and frames over
// a WebSocket (Boost.Beast), on one io thread (the caller's). Binding comes
// first and apart, so a port in use or a bad address is refused before
// anything is loaded or served. A page's messages are parsed here
// (view_message.h); a refused one is logged in one line and the page, the
// other pages and the server go on.
#pragma once

#include "view/view_hub.h"

#include <functional>
#include <memory>
#include <string>

namespace yv {

struct ViewServerOptions {
    std::string bind = "127.0.0.1";
    int port = 8080; ///< 0: any free port (port() says which)
    int maxPages = 16; ///< WebSockets open at once; more are refused
};

class ViewServer {
  public:
    using Log = std::function<void(const std::string&)>;
    /// Binds `options.bind`:`options.port`. Throws yv::Error in one line (an
    /// address that does not parse, a port in use or not allowed).
    ViewServer(const ViewServerOptions& options, Log log);
    ~ViewServer();
    ViewServer(const ViewServer&) = delete;
    ViewServer& operator=(const ViewServer&) = delete;

    /// The port bound (the one the system chose for port 0).
    int port() const;

    /// Listens and serves on the calling thread: pages join `hub` and get
    /// `hello` first. Returns once `stopWanted()` (asked every 100 ms) says
    /// so, every connection closed.
    void serve(ViewHub& hub, const std::string& hello, const std::function<bool()>& stopWanted);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace yv

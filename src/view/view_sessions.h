// The connections of the view server (Boost.Beast, all on the server's one
// io thread): an HTTP session that serves the page and hands a WebSocket
// upgrade over, and the WebSocket session of one page. Internal to
// view_server.cpp's layer: the only header of src/view/ that includes Beast.
#pragma once

#include "view/view_hub.h"

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/http/message.hpp>
#include <boost/beast/http/string_body.hpp>

#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace yv {

class WsSession;

/// What every session of one server shares.
struct SessionShared {
    ViewHub* hub = nullptr;
    std::string hello;
    std::function<void(const std::string&)> log;
    int maxPages = 16;
    std::vector<std::weak_ptr<WsSession>> pages; ///< io thread only
    int openPages();                             ///< drops the closed ones
};

/// Reads one HTTP request from `socket`: the page's files, or the upgrade to a page's WebSocket.
void startHttpSession(boost::asio::ip::tcp::socket socket, SessionShared& shared);

/// Takes over `stream` after the upgrade request `request` and speaks the view protocol.
void startWsSession(boost::beast::tcp_stream stream, boost::beast::http::request<boost::beast::http::string_body> request,
                    SessionShared& shared);

/// Closes a page's WebSocket (the server stops).
void closeWsSession(WsSession& session);

} // namespace yv

// One page's WebSocket: text messages in, parsed and applied to the page's
// wanted state; frames out, the newest winning. A frame is a stats text and
// the JPEG after it; while one is being written, a newer frame replaces the
// one waiting (never a queue of stale frames). Notices (refusals) wait in a
// short queue of their own and go before the next frame.
#include "view/view_message.h"
#include "view/view_sessions.h"

#include "core/error.h"

#include <boost/asio/post.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

#include <deque>
#include <optional>

namespace yv {

namespace beast = boost::beast;
namespace websocket = beast::websocket;

class WsSession : public std::enable_shared_from_this<WsSession> {
  public:
    WsSession(beast::tcp_stream stream, SessionShared& shared) : ws_(std::move(stream)), shared_(shared) {
        beast::error_code ec;
        const auto remote = beast::get_lowest_layer(ws_).socket().remote_endpoint(ec);
        peer_ = ec ? std::string("a page") : remote.address().to_string() + ":" + std::to_string(remote.port());
    }

    void start(beast::http::request<beast::http::string_body> request) {
        ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
        ws_.read_message_max(kMaxViewMessageBytes);
        ws_.async_accept(request, [self = shared_from_this()](beast::error_code ec) { self->onAccept(ec); });
    }

    /// Queues `out` (on the io thread): a frame replaces the frame waiting, a
    /// picture to keep (a screenshot) waits in a short queue of its own, a text alone joins the notices.
    void send(Outgoing out) {
        if (closed_) return;
        if (out.jpeg && out.keep) {
            if (kept_.size() < 4) kept_.push_back(std::move(out));
        } else if (out.jpeg) frame_ = std::move(out);
        else if (notices_.size() < 16) notices_.push_back(std::move(out.text));
        writeNext();
    }

    /// Closes once no write is under way (Beast allows one at a time, a close included).
    void close() {
        if (closed_) return;
        closed_ = true;
        if (!writing_) closeNow();
    }

  private:
    void onAccept(beast::error_code ec) {
        if (ec) return;
        if (shared_.openPages() >= shared_.maxPages) {
            shared_.log("refused a page from " + peer_ + ": " + std::to_string(shared_.maxPages) + " are open already");
            return close();
        }
        shared_.pages.push_back(weak_from_this());
        std::weak_ptr<WsSession> weak = weak_from_this();
        auto executor = ws_.get_executor();
        client_ = shared_.hub->join([weak, executor](Outgoing out) {
            // From the render thread onto the io thread, where the socket is.
            boost::asio::post(executor, [weak, out = std::move(out)]() mutable {
                if (auto self = weak.lock()) self->send(std::move(out));
            });
        });
        notices_.push_back(shared_.hello);
        writeNext();
        read();
    }

    void read() {
        ws_.async_read(in_, [self = shared_from_this()](beast::error_code ec, std::size_t) { self->onRead(ec); });
    }

    void onRead(beast::error_code ec) {
        if (ec == websocket::error::message_too_big) {
            // Beast closes the stream itself (status 1009): logged, and no notice written over its close.
            logRefusal("a message over " + std::to_string(kMaxViewMessageBytes) + " bytes; the connection is closed");
            return leave();
        }
        if (ec) return leave();
        const std::string text = beast::buffers_to_string(in_.data());
        in_.consume(in_.size());
        if (!ws_.got_text()) {
            refuse("a binary message (the page sends JSON text)");
        } else {
            try {
                shared_.hub->apply(*client_, parseViewMessage(text));
            } catch (const Error& e) {
                refuse(e.what());
            }
        }
        read();
    }

    /// One line in the server's log (the first few a page, then a count), and a notice to the page.
    void refuse(const std::string& why) {
        logRefusal(why);
        send(Outgoing{nlohmann::json{{"type", "notice"}, {"text", "refused: " + why}}.dump(), nullptr});
    }

    void logRefusal(const std::string& why) {
        ++refused_;
        if (refused_ <= 10) shared_.log("refused a message from " + peer_ + ": " + why);
        if (refused_ == 10) shared_.log("further refusals from " + peer_ + " are not logged");
    }

    void leave() {
        closed_ = true;
        if (client_) shared_.hub->leave(client_);
        client_.reset();
    }

    void writeNext() {
        if (writing_ || closed_) return;
        if (!notices_.empty()) {
            current_ = std::move(notices_.front());
            notices_.pop_front();
            return writeText(nullptr);
        }
        if (!kept_.empty()) {
            current_ = std::move(kept_.front().text);
            auto jpeg = std::move(kept_.front().jpeg);
            kept_.pop_front();
            return writeText(std::move(jpeg));
        }
        if (!frame_) return;
        current_ = std::move(frame_->text);
        auto jpeg = std::move(frame_->jpeg);
        frame_.reset();
        writeText(std::move(jpeg));
    }

    /// Writes current_ as text, then `jpeg` (when a frame) as binary, then what waits.
    void writeText(std::shared_ptr<const std::vector<std::uint8_t>> jpeg) {
        writing_ = true;
        ws_.text(true);
        ws_.async_write(boost::asio::buffer(current_), [self = shared_from_this(), jpeg](beast::error_code ec, std::size_t) {
            if (ec) return self->leave();
            if (!jpeg) return self->wrote();
            self->ws_.binary(true);
            self->ws_.async_write(boost::asio::buffer(*jpeg), [self, jpeg](beast::error_code ec2, std::size_t) {
                if (ec2) return self->leave();
                self->wrote();
            });
        });
    }

    void wrote() {
        writing_ = false;
        if (closed_ && client_) return closeNow();
        writeNext();
    }

    void closeNow() {
        if (client_) shared_.hub->leave(client_);
        client_.reset();
        ws_.async_close(websocket::close_code::going_away, [self = shared_from_this()](beast::error_code) {});
    }

    websocket::stream<beast::tcp_stream> ws_;
    SessionShared& shared_;
    std::string peer_;
    std::shared_ptr<ViewHub::Client> client_;
    beast::flat_buffer in_;
    std::string current_;
    std::optional<Outgoing> frame_;
    std::deque<std::string> notices_;
    std::deque<Outgoing> kept_;
    bool writing_ = false, closed_ = false;
    int refused_ = 0;
};

void startWsSession(beast::tcp_stream stream, beast::http::request<beast::http::string_body> request, SessionShared& shared) {
    std::make_shared<WsSession>(std::move(stream), shared)->start(std::move(request));
}

void closeWsSession(WsSession& session) { session.close(); }

} // namespace yv

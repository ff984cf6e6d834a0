// One WebSocket client, over plain TCP or TLS (`Stream`): reads messages into its protocol
// and writes what the protocol sends through the Outbox. Every handler runs on the
// connection's strand; the Connection functions post onto it, so other threads never
// touch the socket.
#pragma once

#include <array>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include "server/web/ws/connection.h"
#include "server/web/ws/outbox.h"

namespace omniview::web {

namespace beast = boost::beast;
namespace net = boost::asio;

using ProtocolFactory = std::function<std::unique_ptr<Protocol>(std::shared_ptr<Connection>)>;

struct WsLimits {
  size_t max_message_bytes = 64 << 10;  // a client's message; beyond: closed with 1009
  size_t max_pending_bytes = 16 << 20;  // unsent replies; beyond: closed with 1008
};

template <class Stream>
class WsSession : public Connection, public std::enable_shared_from_this<WsSession<Stream>> {
 public:
  // `slot` is held for the connection's lifetime (the server's connection count).
  WsSession(Stream&& stream, std::string peer, WsLimits limits, std::shared_ptr<void> slot)
      : ws_(std::move(stream)), peer_(std::move(peer)), outbox_(limits.max_pending_bytes), slot_(std::move(slot)) {
    ws_.read_message_max(limits.max_message_bytes);
  }
  ~WsSession() override {
    if (protocol_) protocol_->on_close();
  }

  void start(beast::http::request<beast::http::string_body> request, std::string subprotocol, ProtocolFactory make) {
    // Pings while idle notice a client whose network vanished (Wi-Fi) within ~20 s.
    auto timeout = beast::websocket::stream_base::timeout::suggested(beast::role_type::server);
    timeout.idle_timeout = std::chrono::seconds(20);
    timeout.keep_alive_pings = true;
    ws_.set_option(timeout);
    ws_.set_option(beast::websocket::stream_base::decorator([subprotocol](beast::websocket::response_type& res) {
      res.set(beast::http::field::server, "omniviewd");
      if (!subprotocol.empty()) res.set(beast::http::field::sec_websocket_protocol, subprotocol);
    }));
    make_ = std::move(make);
    request_ = std::move(request);
    ws_.async_accept(request_, beast::bind_front_handler(&WsSession::on_accept, this->shared_from_this()));
  }

  void send_text(std::string text) override {
    net::post(ws_.get_executor(), [self = this->shared_from_this(), text = std::move(text)]() mutable {
      if (self->finished_ || self->close_sent_) return;
      if (!self->outbox_.push_text(std::move(text))) {
        self->begin_close(1008, "too many unread replies: this client does not read");
        return;
      }
      self->write_next();
    });
  }

  void send_latest(uint32_t channel, OutMessage message, std::function<void(bool)> done) override {
    net::post(ws_.get_executor(), [self = this->shared_from_this(), channel, message = std::move(message),
                                   done = std::move(done)]() mutable {
      if (self->finished_ || self->closing_) {
        if (done) done(false);
        return;
      }
      self->outbox_.push_latest(channel, std::move(message), std::move(done));
      self->write_next();
    });
  }

  void close(uint16_t code, std::string reason) override {
    net::post(ws_.get_executor(), [self = this->shared_from_this(), code, reason = std::move(reason)]() {
      self->begin_close(code, reason);
    });
  }

  void after(std::chrono::milliseconds delay, std::function<void()> task) override {
    net::post(ws_.get_executor(), [self = this->shared_from_this(), delay, task = std::move(task)]() mutable {
      if (self->finished_) return;
      auto timer = std::make_shared<net::steady_timer>(self->ws_.get_executor(), delay);
      timer->async_wait([self, timer, task = std::move(task)](beast::error_code ec) {
        if (!ec && !self->finished_) self->guarded(task);
      });
    });
  }

  const std::string& peer() const override { return peer_; }

 private:
  void on_accept(beast::error_code ec) {
    if (ec) return finish();
    if (!guarded([this] {
          protocol_ = make_(this->shared_from_this());
          protocol_->on_open();
        })) {
      return;
    }
    read_next();
  }

  // Runs a protocol's handler. Protocols answer bad input themselves (a status message, an
  // error reply); an exception that still escapes one is a bug, and ends this client's
  // connection with 1011 ("internal error"), logged, never the daemon. True if none escaped.
  template <class Handler>
  bool guarded(Handler&& handler) {
    std::string why;
    try {
      handler();
      return true;
    } catch (const std::exception& e) {
      why = e.what();
    } catch (...) {
      why = "an exception of unknown type";
    }
    std::cerr << "omniviewd: web: " << peer_ << ": internal error: " << why << ": connection closed" << std::endl;
    begin_close(1011, "internal server error");
    return false;
  }

  void read_next() {
    ws_.async_read(buffer_, beast::bind_front_handler(&WsSession::on_read, this->shared_from_this()));
  }

  void on_read(beast::error_code ec, size_t) {
    if (ec == beast::websocket::error::message_too_big) {
      std::cerr << "omniviewd: web: " << peer_ << " sent a message over web.max_message_bytes: closed" << std::endl;
      return finish();  // Beast has already sent close 1009 ("message too big")
    }
    if (ec) return finish();
    const auto data = buffer_.cdata();
    const std::string_view message(static_cast<const char*>(data.data()), data.size());
    const bool handled = guarded([&] { protocol_->on_message(message, !ws_.got_text()); });
    buffer_.consume(buffer_.size());
    if (handled && !finished_) read_next();
  }

  void write_next() {
    if (writing_ || finished_ || close_sent_) return;
    auto next = outbox_.pop();
    if (!next) {
      if (closing_ && !close_sent_) send_close();
      return;
    }
    writing_ = true;
    current_ = std::move(*next);
    ws_.binary(current_.message.binary);
    const std::array<net::const_buffer, 2> buffers{
        net::buffer(current_.message.head),
        net::buffer(current_.message.body.data(), current_.message.body.size())};
    ws_.async_write(buffers, beast::bind_front_handler(&WsSession::on_write, this->shared_from_this()));
  }

  void on_write(beast::error_code ec, size_t) {
    writing_ = false;
    auto done = std::move(current_.done);
    current_ = {};
    if (done) done(!ec);
    if (ec) return finish();
    write_next();
  }

  // Sends the replies still queued, then the close frame.
  void begin_close(uint16_t code, const std::string& reason) {
    if (finished_ || closing_) return;
    closing_ = true;
    close_reason_ = beast::websocket::close_reason(static_cast<beast::websocket::close_code>(code), reason.substr(0, 123));
    // Frames are not worth waiting for; replies are (the refusal that explains the close).
    outbox_.drop_channels();
    write_next();  // the replies left, then the close frame
  }

  void send_close() {
    close_sent_ = true;
    ws_.async_close(close_reason_, [self = this->shared_from_this()](beast::error_code) { self->finish(); });
  }

  void finish() {
    if (finished_) return;
    finished_ = true;
    outbox_.drop_all();
    if (protocol_) protocol_->on_close();
  }

  beast::websocket::stream<Stream> ws_;
  const std::string peer_;
  Outbox outbox_;
  std::shared_ptr<void> slot_;
  beast::http::request<beast::http::string_body> request_;
  ProtocolFactory make_;
  std::unique_ptr<Protocol> protocol_;
  beast::flat_buffer buffer_;
  Outbox::Next current_;
  bool writing_ = false;
  bool closing_ = false;
  bool close_sent_ = false;
  bool finished_ = false;
  beast::websocket::close_reason close_reason_;
};

}  // namespace omniview::web

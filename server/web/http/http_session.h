// One HTTP/1.1 connection (plain or TLS): GET/HEAD of the console's files, keep-alive, and
// the hand-over to a WebSocket session on an upgrade request. Beast parses; nothing here
// reads raw bytes.
#pragma once

#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>

#include "server/web/http/endpoint.h"
#include "server/web/http/static_files.h"

namespace omniview::web {

namespace http = beast::http;

inline void shutdown_stream(beast::tcp_stream& s) {
  beast::error_code ec;
  s.socket().shutdown(net::ip::tcp::socket::shutdown_send, ec);
}
template <class Handler>
void async_shutdown_stream(beast::tcp_stream& s, Handler&& done) {
  shutdown_stream(s);
  done();
}
template <class Handler>
void async_shutdown_stream(beast::ssl_stream<beast::tcp_stream>& s, Handler&& done) {
  s.async_shutdown([done = std::forward<Handler>(done)](beast::error_code) mutable { done(); });
}

template <class Stream>
class HttpSession : public std::enable_shared_from_this<HttpSession<Stream>> {
  using Response = http::response<http::string_body>;

 public:
  HttpSession(Stream&& stream, std::string peer, Endpoint& endpoint, std::shared_ptr<void> slot)
      : stream_(std::move(stream)), peer_(std::move(peer)), endpoint_(endpoint), slot_(std::move(slot)) {}

  void run() { read_next(); }

 private:
  void read_next() {
    parser_.emplace();
    parser_->header_limit(8 << 10);
    // A WHEP offer (a browser's is ~6 KB, every codec listed) fits even where WebSocket
    // messages are held smaller.
    parser_->body_limit(std::max<size_t>(endpoint_.ws_limits().max_message_bytes, 64 << 10));
    // An idle keep-alive connection gives its place back soon (web.max_connections).
    beast::get_lowest_layer(stream_).expires_after(std::chrono::seconds(15));
    http::async_read(stream_, buffer_, *parser_,
                     beast::bind_front_handler(&HttpSession::on_read, this->shared_from_this()));
  }

  void on_read(beast::error_code ec, size_t) {
    if (ec == http::error::end_of_stream) return close();
    if (ec) {
      // A request too large or malformed gets a reason, not silence.
      if (ec == http::error::header_limit || ec == http::error::body_limit) {
        return reply(http::status::payload_too_large, "request too large\n", false);
      }
      if (ec != net::error::operation_aborted && ec != beast::error::timeout) {
        return reply(http::status::bad_request, "malformed HTTP request: " + ec.message() + "\n", false);
      }
      return;
    }
    Request request = parser_->release();
    // An exception out of the handling below is a bug: the client gets a 500, the daemon
    // keeps serving everyone else.
    try {
      handle(std::move(request));
    } catch (const std::exception& e) {
      internal_error(e.what());
    } catch (...) {
      internal_error("an exception of unknown type");
    }
  }

  void internal_error(const std::string& why) {
    std::cerr << "omniviewd: web: " << peer_ << ": internal error: " << why << std::endl;
    reply(http::status::internal_server_error, "internal server error\n", false);
  }

  void handle(Request request) {
    // RFC 9112 3.2: an HTTP/1.1 request without exactly one Host header is a 400.
    if (request.version() >= 11 && request.count(http::field::host) != 1) {
      return reply(http::status::bad_request, "an HTTP/1.1 request needs exactly one Host header\n", false,
                   request.version());
    }
    if (beast::websocket::is_upgrade(request)) return upgrade(std::move(request));
    const bool keep_alive = request.keep_alive(), head = request.method() == http::verb::head;
    const unsigned version = request.version();
    const bool routed = endpoint_.route(request, peer_, [self = this->shared_from_this(), keep_alive, version,
                                                        head](HttpReply r) {
      // Back on the connection's strand: the stream is used there only.
      net::post(self->stream_.get_executor(), [self, r = std::move(r), keep_alive, version, head]() mutable {
        auto res = std::make_shared<Response>(static_cast<http::status>(r.status), version);
        self->decorate(*res, r.content_type);
        for (auto& [name, value] : r.headers) res->insert(name, value);
        res->keep_alive(keep_alive);
        set_body(*res, std::move(r.body), head);
        self->send(res);
      });
    });
    if (routed) return;
    if (request.method() != http::verb::get && request.method() != http::verb::head) {
      return reply(http::status::method_not_allowed, "only GET and HEAD are served here\n", request);
    }
    const auto found = endpoint_.files().find(std::string(request.target()));
    if (found.status != 200) {
      return reply(static_cast<http::status>(found.status), found.status == 404 ? "not found\n" : "bad path\n",
                   request);
    }
    // Read whole: the console's files are small (the largest, three.js, ~1 MB), and one
    // body type for every reply compiles one write path per stream, not three.
    std::optional<std::string> body = read_file(found.file);
    if (!body) return reply(http::status::not_found, "not found\n", request);
    auto res = std::make_shared<Response>(http::status::ok, request.version());
    decorate(*res, found.content_type);
    res->keep_alive(request.keep_alive());
    set_body(*res, std::move(*body), request.method() == http::verb::head);
    send(res);
  }

  // A HEAD reply says what the GET's would (its Content-Length) and sends no body: a
  // body there would be read as the start of the next reply on a kept-alive connection.
  static void set_body(Response& res, std::string body, bool head) {
    if (head) {
      res.content_length(body.size());
    } else {
      res.body() = std::move(body);
      res.prepare_payload();
    }
  }

  void decorate(Response& res, const std::string& type) {
    res.set(http::field::server, "omniviewd");
    res.set(http::field::content_type, type);
    // The console is always the daemon's current one; the browser asks again (304-free: small files).
    res.set(http::field::cache_control, "no-cache");
    res.set("X-Content-Type-Options", "nosniff");
    res.set("Content-Security-Policy",
            "default-src 'self'; img-src 'self' blob: data:; connect-src 'self' ws: wss:; frame-ancestors 'none'");
  }

  void upgrade(Request request) {
    const UpgradeDecision decision = endpoint_.upgrade(request, peer_);
    if (decision.status != 101) {
      return reply(static_cast<http::status>(decision.status), decision.message + "\n", false, request.version());
    }
    beast::get_lowest_layer(stream_).expires_never();  // the WebSocket keeps its own timeouts
    std::make_shared<WsSession<Stream>>(std::move(stream_), peer_, endpoint_.ws_limits(), std::move(slot_))
        ->start(std::move(request), decision.subprotocol, decision.make);
  }

  // A short text reply to a request that was read (keep-alive and HEAD as it asked).
  void reply(http::status status, std::string text, const Request& request) {
    reply(status, std::move(text), request.keep_alive(), request.version(), request.method() == http::verb::head);
  }

  void reply(http::status status, std::string text, bool keep_alive, unsigned version = 11, bool head = false) {
    auto res = std::make_shared<Response>(status, version);
    decorate(*res, "text/plain; charset=utf-8");
    res->keep_alive(keep_alive);
    set_body(*res, std::move(text), head);
    send(res);
  }

  void send(std::shared_ptr<Response> res) {
    http::async_write(stream_, *res,
                      [self = this->shared_from_this(), res](beast::error_code ec, size_t) {
                        if (ec || !res->keep_alive()) return self->close();
                        self->read_next();
                      });
  }

  void close() {
    async_shutdown_stream(stream_, [self = this->shared_from_this()] {});
  }

  Stream stream_;
  const std::string peer_;
  Endpoint& endpoint_;
  std::shared_ptr<void> slot_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
};

}  // namespace omniview::web

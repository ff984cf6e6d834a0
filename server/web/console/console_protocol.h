// The operator console's protocol ("omniview.console.v1", docs/API.md "Web endpoint"):
// JSON text messages for authentication, the API's unary calls and subscriptions; each
// subscribed view's frames as binary messages (stream/frame_message.h).
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "server/web/json/json.h"
#include "server/web/stream/stream.h"
#include "server/web/web_context.h"
#include "server/web/ws/connection.h"

namespace omniview::web {

inline constexpr char kConsoleSubprotocol[] = "omniview.console.v1";
// The ops a console message may name, each in server/auth/permissions.h as "console:OP".
inline constexpr const char* kConsoleOps[] = {"auth", "call", "subscribe", "subscribe_cloud", "unsubscribe"};

class ConsoleProtocol : public Protocol {
 public:
  // `caller`: set when the upgrade request carried a valid token (Authorization header);
  // else, with tokens configured, the client's first message must be {"op": "auth"}.
  ConsoleProtocol(std::weak_ptr<Connection> connection, const WebContext& context, std::optional<Caller> caller);
  ~ConsoleProtocol() override;

  void on_open() override;
  void on_message(std::string_view data, bool binary) override;
  void on_close() override;

 private:
  void handle(const json::Value& message, std::optional<int64_t> id);
  void authenticate(const json::Value& message, std::optional<int64_t> id);
  void call(const json::Value& message, std::optional<int64_t> id);
  void subscribe(const json::Value& message, std::optional<int64_t> id);
  void subscribe_cloud(const json::Value& message, std::optional<int64_t> id);
  bool check_stream_limit(std::optional<int64_t> id);
  void unsubscribe(const json::Value& message, std::optional<int64_t> id);

  void reply(std::optional<int64_t> id, const std::string& response_json);
  void fail(std::optional<int64_t> id, ErrorKind kind, const std::string& message);
  void send(std::string text);

  std::weak_ptr<Connection> connection_;
  const WebContext& context_;
  std::optional<Caller> caller_;
  std::string peer_;
  std::map<uint32_t, Stream> channels_;
  uint32_t next_channel_ = 1;
  std::shared_ptr<std::atomic<int>> calls_in_flight_ = std::make_shared<std::atomic<int>>(0);
  bool closed_ = false;
};

}  // namespace omniview::web

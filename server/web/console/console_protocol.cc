#include "server/web/console/console_protocol.h"

#include <sstream>

#include <boost/asio/post.hpp>

#include "server/api/request_bounds.h"
#include "server/auth/permissions.h"
#include "server/pipeline/cloud/cloud_request.h"
#include "server/pipeline/frame_encoder.h"
#include "server/web/stream/frame_message.h"

namespace omniview::web {

namespace {

constexpr int kMaxCallsInFlight = 4;  // per client: a joystick waits for its reply before the next step
constexpr auto kAuthTimeout = std::chrono::seconds(10);  // a connection that never authenticates is closed

// What a subscription that ended on its own (its view deleted, the daemon stopping) tells
// the client (Stream silences it for an unsubscribe).
template <class AnySubscriber>
std::function<void(const AnySubscriber&)> ended_notice(std::weak_ptr<Connection> connection, uint32_t channel) {
  return [connection = std::move(connection), channel](const AnySubscriber& subscriber) {
    if (const auto c = connection.lock()) {
      c->send_text("{\"op\":\"ended\",\"channel\":" + std::to_string(channel) + ",\"error\":{\"code\":" +
                   json::quote(status_name(subscriber.close_kind())) +
                   ",\"message\":" + json::quote(subscriber.close_reason()) + "}}");
    }
  };
}

const std::string kOps = [] {
  std::string list;
  for (const char* op : kConsoleOps) list += (list.empty() ? "" : ", ") + std::string(op);
  return list;
}();

std::string number_text(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

}  // namespace

ConsoleProtocol::ConsoleProtocol(std::weak_ptr<Connection> connection, const WebContext& context,
                                 std::optional<Caller> caller)
    : connection_(std::move(connection)), context_(context), caller_(std::move(caller)) {
  if (const auto c = connection_.lock()) peer_ = c->peer();
}

ConsoleProtocol::~ConsoleProtocol() { on_close(); }

void ConsoleProtocol::send(std::string text) {
  if (const auto c = connection_.lock()) c->send_text(std::move(text));
}

void ConsoleProtocol::reply(std::optional<int64_t> id, const std::string& response_json) {
  send("{\"op\":\"reply\",\"id\":" + (id ? std::to_string(*id) : "null") + ",\"response\":" + response_json + "}");
}

void ConsoleProtocol::fail(std::optional<int64_t> id, ErrorKind kind, const std::string& message) {
  const std::string error = "{\"code\":" + json::quote(status_name(kind)) + ",\"message\":" + json::quote(message) + "}";
  if (id) {
    send("{\"op\":\"reply\",\"id\":" + std::to_string(*id) + ",\"error\":" + error + "}");
  } else {
    send("{\"op\":\"error\",\"error\":" + error + "}");
  }
}

void ConsoleProtocol::on_open() {
  const bool need = context_.auth.enabled() && !caller_;
  std::string hello = "{\"op\":\"hello\",\"protocol\":" + json::quote(kConsoleSubprotocol) +
                      ",\"server\":\"omniviewd\",\"version\":" + json::quote(OMNIVIEW_VERSION) +
                      ",\"auth\":" + json::quote(need ? "required" : "done");
  if (caller_) hello += ",\"role\":" + json::quote(to_string(caller_->role));
  send(hello + "}");
  if (need) {
    if (const auto c = connection_.lock()) {
      c->after(kAuthTimeout, [this] {
        if (caller_) return;
        if (const auto conn = connection_.lock()) conn->close(1008, "no auth message within 10 s");
      });
    }
  }
}

void ConsoleProtocol::on_message(std::string_view data, bool binary) {
  if (binary) {
    return fail(std::nullopt, ErrorKind::kInvalidArgument,
                "binary messages are not part of omniview.console.v1: send JSON text");
  }
  std::string error;
  const auto message = json::parse_object(data, &error);
  if (!message) return fail(std::nullopt, ErrorKind::kInvalidArgument, error);
  std::optional<int64_t> id;
  try {
    id = json::integer_field(*message, "id", 0, int64_t{1} << 52);
    handle(*message, id);
  } catch (...) {
    const Failure failure = current_failure();
    fail(id, failure.kind, failure.message);
  }
}

void ConsoleProtocol::handle(const json::Value& message, std::optional<int64_t> id) {
  const auto op = json::string_field(message, "op");
  if (!op) throw std::invalid_argument("no 'op' (one of: " + kOps + ")");
  if (*op == "auth") return authenticate(message, id);
  if (!caller_) {
    if (context_.auth.enabled()) {
      return fail(id, ErrorKind::kUnauthenticated, "send {\"op\": \"auth\", \"token\": ...} first");
    }
    caller_ = Caller{Role::kOperator, ""};
  }
  // Each op's role from the one table (server/auth/permissions.h); `call` checks the called
  // RPC's role besides.
  if (const auto needed = permissions::role_for("console:" + *op); needed && !role_allows(caller_->role, *needed)) {
    const std::string why = "'" + *op + "' needs the " + to_string(*needed) + " role; this connection's token is a " +
                            to_string(caller_->role) + " token";
    context_.refused(peer_, why);
    return fail(id, ErrorKind::kPermissionDenied, why);
  }
  if (*op == "call") return call(message, id);
  if (*op == "subscribe") return subscribe(message, id);
  if (*op == "subscribe_cloud") return subscribe_cloud(message, id);
  if (*op == "unsubscribe") return unsubscribe(message, id);
  throw std::invalid_argument("unknown op '" + *op + "' (one of: " + kOps + ")");
}

void ConsoleProtocol::authenticate(const json::Value& message, std::optional<int64_t> id) {
  const auto token = json::string_field(message, "token").value_or("");
  Caller caller;
  const grpc::Status s = context_.auth.check_header("Bearer " + token, Role::kViewer, &caller);
  if (!s.ok()) {
    context_.refused(peer_, s.error_message());
    fail(id, kind_of(s.error_code()), s.error_message());
    // A wrong token ends the connection: guessing costs a new connection each time.
    if (const auto c = connection_.lock()) c->close(1008, s.error_message());
    return;
  }
  caller_ = caller;
  if (context_.auth.enabled()) context_.authenticated(peer_, kConsoleSubprotocol, caller);
  reply(id, "{\"role\":" + json::quote(to_string(caller.role)) + "}");
}

void ConsoleProtocol::call(const json::Value& message, std::optional<int64_t> id) {
  const auto method = json::string_field(message, "method");
  if (!method) throw std::invalid_argument("'call' needs a 'method' (e.g. \"UpdateView\")");
  const auto role = context_.calls.role_of(*method);
  if (!role) {
    std::string list;
    for (const auto& m : context_.calls.methods()) list += (list.empty() ? "" : ", ") + m;
    return fail(id, ErrorKind::kUnimplemented, "no method '" + *method + "' here (methods: " + list + ")");
  }
  if (!role_allows(caller_->role, *role)) {
    const std::string why = *method + " needs the " + to_string(*role) + " role; this connection's token is a " +
                            to_string(caller_->role) + " token";
    context_.refused(peer_, why);
    return fail(id, ErrorKind::kPermissionDenied, why);
  }
  if (*calls_in_flight_ >= kMaxCallsInFlight) {
    return fail(id, ErrorKind::kResourceExhausted,
                "more than " + std::to_string(kMaxCallsInFlight) + " calls in flight: wait for their replies");
  }
  const json::Value* request = json::find(message, "request");
  if (request && !request->is_object() && !request->is_null()) {
    throw std::invalid_argument("'request' must be an object (the API's request message as JSON)");
  }
  const std::string text = request && request->is_object() ? json::to_text(*request) : "";
  ++*calls_in_flight_;
  // Off the I/O thread: UpdateView returns only once the view's new map is built.
  boost::asio::post(context_.workers, [connection = connection_, calls = &context_.calls, in_flight = calls_in_flight_,
                                       method = *method, text, id] {
    ApiCalls::Result result;
    try {  // call() turns errors into statuses; nothing may end the worker thread anyway
      result = calls->call(method, text);
    } catch (...) {
      result.status = grpc_status(current_failure());
    }
    --*in_flight;
    const auto c = connection.lock();
    if (!c) return;
    const std::string head = "{\"op\":\"reply\",\"id\":" + (id ? std::to_string(*id) : "null");
    if (result.status.ok()) {
      c->send_text(head + ",\"response\":" + result.response + "}");
    } else {
      c->send_text(head + ",\"error\":{\"code\":" + json::quote(status_name(kind_of(result.status.error_code()))) +
                   ",\"message\":" + json::quote(result.status.error_message()) + "}}");
    }
  });
}

bool ConsoleProtocol::check_stream_limit(std::optional<int64_t> id) {
  if (static_cast<int>(channels_.size()) < context_.limits.max_streams_per_client) return true;
  fail(id, ErrorKind::kResourceExhausted,
       "at most " + std::to_string(context_.limits.max_streams_per_client) +
           " streams per connection (limits.max_streams_per_client): unsubscribe one first");
  return false;
}

void ConsoleProtocol::subscribe(const json::Value& message, std::optional<int64_t> id) {
  const auto view = json::string_field(message, "view");
  if (!view || view->empty()) throw std::invalid_argument("'subscribe' needs a 'view'");
  if (!check_stream_limit(id)) return;
  v1::Encoding encoding = v1::JPEG;
  if (const auto name = json::string_field(message, "encoding")) {
    if (!v1::Encoding_Parse(*name, &encoding)) throw std::invalid_argument("'encoding' must be JPEG, PNG, RAW or H264");
  }
  const int quality = static_cast<int>(json::integer_field(message, "quality", 0, 100).value_or(0));
  const bool gray = json::bool_field(message, "gray").value_or(false);
  const int kbps = static_cast<int>(json::integer_field(message, "max_bitrate_kbps", 0, INT32_MAX).value_or(0));
  const EncodingKey key = encoding_key(encoding, quality, gray, kbps);
  const double asked = json::number_field(message, "max_rate_hz").value_or(0);
  if (asked < 0) throw std::invalid_argument("'max_rate_hz' must be >= 0 (0: as fast as frames come)");
  const double rate = asked == 0 ? context_.limits.max_rate_hz : std::min(asked, context_.limits.max_rate_hz);
  const bool stale = json::bool_field(message, "stale_frames").value_or(true);

  auto subscription = context_.pipeline.subscribe(*view, peer_ + " (web)", key, rate, stale);  // or NOT_FOUND
  const uint32_t channel = next_channel_++;
  auto source = subscriber_source(
      subscription.shared(), [channel](const SharedFrame& frame) { return frame_message(channel, frame); },
      ended_notice<Subscriber>(connection_, channel));
  channels_.try_emplace(channel, connection_, channel, std::move(source), release_of(std::move(subscription)));
  reply(id, "{\"channel\":" + std::to_string(channel) + ",\"view\":" + json::quote(*view) +
                ",\"maxRateHz\":" + number_text(rate) + ",\"encoding\":" + json::quote(to_string(key)) + "}");
}

void ConsoleProtocol::subscribe_cloud(const json::Value& message, std::optional<int64_t> id) {
  // The request is StreamClouds' own message, checked as the gRPC call checks it.
  v1::StreamCloudsRequest request;
  if (const json::Value* r = json::find(message, "request")) {
    if (!r->is_object()) throw std::invalid_argument("'request' must be an object (a StreamCloudsRequest)");
    if (const auto error = json::text_to_message(json::to_text(*r), request); !error.empty()) {
      throw std::invalid_argument("request is not a StreamCloudsRequest: " + error);
    }
  }
  if (const grpc::Status s = check_request_bounds(request); !s.ok()) return fail(id, kind_of(s.error_code()), s.error_message());
  if (!check_stream_limit(id)) return;
  const double rate = request.max_rate_hz() == 0 ? context_.limits.max_rate_hz
                                                 : std::min(request.max_rate_hz(), context_.limits.max_rate_hz);
  auto subscription = context_.pipeline.subscribe_cloud(request.source(), peer_ + " (web)",
                                                        cloud_request_from_proto(request.options()), rate);
  const uint32_t channel = next_channel_++;
  auto source = subscriber_source(
      subscription.shared(), [channel](const SharedCloud& cloud) { return cloud_message(channel, cloud); },
      ended_notice<CloudSubscriber>(connection_, channel));
  channels_.try_emplace(channel, connection_, channel, std::move(source), release_of(std::move(subscription)));
  reply(id, "{\"channel\":" + std::to_string(channel) + ",\"maxRateHz\":" + number_text(rate) + "}");
}

void ConsoleProtocol::unsubscribe(const json::Value& message, std::optional<int64_t> id) {
  const auto channel = json::integer_field(message, "channel", 0, UINT32_MAX);
  if (!channel) throw std::invalid_argument("'unsubscribe' needs a 'channel'");
  if (!channels_.count(static_cast<uint32_t>(*channel))) {
    return fail(id, ErrorKind::kNotFound, "no channel " + std::to_string(*channel) + " on this connection");
  }
  channels_.erase(static_cast<uint32_t>(*channel));  // Stream's end stops its pump and leaves the pipeline
  reply(id, "{}");
}

void ConsoleProtocol::on_close() {
  if (closed_) return;
  closed_ = true;
  channels_.clear();
}

}  // namespace omniview::web

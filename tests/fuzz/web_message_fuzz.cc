// Fuzz target: what a WebSocket client sends the web endpoint. The input's first byte picks
// the protocol and the caller (console before any token, console as viewer, console as
// operator, Foxglove as viewer); the rest is split at NUL bytes into messages, each sent
// as text or binary (bit i % 8 of the second byte for message i), so sequences (auth, then
// a call, then a subscribe) are reached. The handlers run against a real pipeline serving
// the bundled example (web_message_fuzz.yaml: small views, so maps build fast; not
// started: no source runs, calls and subscriptions do). Protocols answer bad input with an error message; an exception
// out of on_message (the crash of issue 33), a crash, a hang or a sanitizer report is a bug.
#include <cstddef>
#include <cstdint>
#include <future>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <boost/asio/post.hpp>
#include <boost/asio/thread_pool.hpp>

#include "server/config/daemon_config.h"
#include "server/daemon/daemon.h"
#include "server/sources/builtin_sources.h"
#include "server/web/console/api_calls.h"
#include "server/web/console/console_protocol.h"
#include "server/web/foxglove/foxglove_protocol.h"
#include "server/web/web_context.h"

namespace {

using namespace omniview;
using namespace omniview::web;

// A client that takes everything: replies are counted, frames declined (the pumps go on).
class SinkConnection : public Connection {
 public:
  void send_text(std::string text) override { replies_ += text.size() > 0; }
  void send_latest(uint32_t, OutMessage, std::function<void(bool)> done) override {
    if (done) done(false);
  }
  void close(uint16_t, std::string) override {}
  void after(std::chrono::milliseconds, std::function<void()>) override {}  // timers never fire here
  const std::string& peer() const override { return peer_; }

 private:
  std::atomic<size_t> replies_{0};
  const std::string peer_ = "ipv4:127.0.0.1:1 (fuzz)";
};

struct World {
  World() {
    register_builtin_sources();
    const DaemonConfig config = load_daemon_config(OMNIVIEW_FUZZ_CONFIG);
    daemon = std::make_unique<Daemon>(config, /*listen=*/false);
    limits = config.limits;
    calls = std::make_unique<ApiCalls>(daemon->pipeline(), limits);
    auth = std::make_unique<Authenticator>(std::vector<TokenConfig>{{"viewer-token", Role::kViewer, "viewer"},
                                                                    {"operator-token", Role::kOperator, "operator"}});
    context = std::make_unique<WebContext>(WebContext{daemon->pipeline(), *auth, *calls, limits, workers,
                                                      [](const std::string&, const std::string&) {},
                                                      [](const std::string&, const std::string&, const Caller&) {}});
  }
  // Every call posted so far has run (one worker: in order).
  void drain() {
    std::promise<void> done;
    boost::asio::post(workers, [&done] { done.set_value(); });
    done.get_future().wait();
  }

  std::unique_ptr<Daemon> daemon;
  Limits limits;
  std::unique_ptr<ApiCalls> calls;
  std::unique_ptr<Authenticator> auth;
  boost::asio::thread_pool workers{1};
  std::unique_ptr<WebContext> context;
};

std::unique_ptr<Protocol> make_protocol(uint8_t choice, const std::shared_ptr<Connection>& connection,
                                        const WebContext& context) {
  switch (choice % 4) {
    case 0: return std::make_unique<ConsoleProtocol>(connection, context, std::nullopt);  // must send auth first
    case 1: return std::make_unique<ConsoleProtocol>(connection, context, Caller{Role::kViewer, "viewer"});
    case 2: return std::make_unique<ConsoleProtocol>(connection, context, Caller{Role::kOperator, "operator"});
    default: return std::make_unique<FoxgloveProtocol>(connection, context, Caller{Role::kViewer, "viewer"});
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static World world;
  if (size < 2) return 0;
  const uint8_t choice = data[0];
  const uint8_t binary_bits = data[1];
  const std::string_view rest(reinterpret_cast<const char*>(data + 2), size - 2);
  auto connection = std::make_shared<SinkConnection>();
  {
    auto protocol = make_protocol(choice, connection, *world.context);
    protocol->on_open();
    size_t start = 0;
    for (int i = 0; start <= rest.size() && i < 32; ++i) {
      const size_t end = std::min(rest.find('\0', start), rest.size());
      protocol->on_message(rest.substr(start, end - start), (binary_bits >> (i % 8)) & 1);
      start = end + 1;
    }
    protocol->on_close();
  }
  world.drain();
  // Views the input made are deleted, so the next input starts from the config's two.
  for (const auto& view : world.daemon->pipeline().list_views()) {
    const std::string& name = view.spec().name();
    if (name != "front" && name != "panorama") world.daemon->pipeline().delete_view(name);
  }
  return 0;
}

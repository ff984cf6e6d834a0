// The config's `web:` block: defaults, keys, ranges, and the exposure rule on web.listen,
// each error naming the file, the line and the key.
#include <gtest/gtest.h>

#include "server/config/daemon_config.h"
#include "test_support.h"

namespace omniview {
namespace {

using testing::expect_throw_containing;

constexpr char kSources[] = "sources:\n  - {name: cam, type: images}\n";  // lines 1-2

DaemonConfig parse(const std::string& text) {
  ListenOptions options;
  options.resolve = [](const std::string& host, std::string*) -> std::vector<std::string> {
    return host == "robot.example" ? std::vector<std::string>{"192.168.1.7"} : std::vector<std::string>{"127.0.0.1"};
  };
  return parse_daemon_config(YamlReader::from_string(std::string(kSources) + text, "d.yaml"), "/cfg", options);
}

void expect_error(const std::string& text, std::initializer_list<std::string> needles) {
  expect_throw_containing<ConfigError>([&] { parse(text); }, needles, text);
}

TEST(WebConfig, OffWithoutABlockAndOnWithOne) {
  EXPECT_FALSE(parse("").web.enabled);
  const auto config = parse("web: {listen: '127.0.0.1:0'}\n");
  EXPECT_TRUE(config.web.enabled);
  EXPECT_EQ(config.web.listen, "127.0.0.1:0");
  EXPECT_EQ(config.web.max_connections, 64);
  EXPECT_EQ(config.web.max_message_bytes, 64 << 10);
  EXPECT_EQ(config.web.javascript_dir, "/usr/share/javascript");
  EXPECT_FALSE(parse("web: {enabled: false, listen: '0.0.0.0:80'}\n").web.enabled);  // off: never judged
  EXPECT_EQ(parse("web: {}\n").web.listen, "127.0.0.1:8765");
}

TEST(WebConfig, BundledConfigsServeOnLoopback) {
  for (const char* file : {"/config/omniviewd.yaml"}) {
    const auto config = load_daemon_config(std::string(OMNIVIEW_SOURCE_DIR) + file);
    EXPECT_TRUE(config.web.enabled) << file;
    EXPECT_EQ(config.web.listen, "127.0.0.1:8765") << file;
  }
}

TEST(WebConfig, ErrorsNameLineAndKey) {
  expect_error("web: [1]\n", {"d.yaml:3", "web", "expected a map"});
  expect_error("web: {listn: x}\n", {"d.yaml:3", "listn"});
  expect_error("web:\n  listen: nope\n", {"d.yaml:4", "web.listen", "not host:port"});
  expect_error("web:\n  listen: unix:/run/x.sock\n", {"d.yaml:4", "web.listen", "TCP only"});
  expect_error("web:\n  max_connections: 0\n", {"d.yaml:4", "web.max_connections", "from 1 to 10000"});
  expect_error("web:\n  max_message_bytes: 10\n", {"d.yaml:4", "web.max_message_bytes"});
  expect_error("web:\n  console_dir: /no/such/folder\n", {"d.yaml:4", "web.console_dir", "not a folder"});
  expect_error("web:\n  enabled: maybe\n", {"d.yaml:4", "web.enabled"});
}

TEST(WebConfig, ATurnServerNeedsItsUserAndPassword) {
  EXPECT_EQ(parse("web:\n  webrtc: {turn_server: 'turn://u:p@relay:3478'}\n").web.webrtc.turn_server,
            "turn://u:p@relay:3478");
  for (const char* url : {"turn://relay:3478", "turn://u@relay:3478", "turns://:p@relay:3478", "turn://u:@relay"}) {
    expect_error(std::string("web:\n  webrtc:\n    turn_server: '") + url + "'\n",
                 {"d.yaml:5", "web.webrtc.turn_server", "USER:PASSWORD"});
  }
  // The error never repeats a password.
  try {
    parse("web:\n  webrtc:\n    turn_server: 'turn://u:secret@'\n");
    ADD_FAILURE() << "accepted a TURN server without a host";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()).find("secret"), std::string::npos) << e.what();
  }
}

TEST(WebConfig, ExposureRuleAsForTheGrpcPort) {
  // Reachable from other machines without TLS and tokens: refused, the web line blamed.
  expect_error("web:\n  listen: 0.0.0.0:8765\n", {"d.yaml:4", "web.listen", "reachable from other machines"});
  expect_error("web:\n  listen: 'robot.example:8765'\n", {"d.yaml:4", "web.listen"});
  expect_error("tokens: [{role: viewer, token: abc}]\nweb:\n  listen: '[::]:8765'\n",
               {"d.yaml:5", "web.listen"});
  // The network is trusted: as for listen.
  EXPECT_NO_THROW(parse("allow_insecure_remote: true\nweb:\n  listen: 0.0.0.0:8765\n"));
  EXPECT_NO_THROW(parse("web:\n  listen: localhost:8765\n"));
}

}  // namespace
}  // namespace omniview

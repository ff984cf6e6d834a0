// Listen address forms, and where the effective address comes from: --listen over
// OMNIVIEW_LISTEN over the file, each blamed for its own mistakes, the exposure rule on the
// result (never on the file's address alone).
#include <gtest/gtest.h>

#include <stdlib.h>

#include "server/config/daemon_config.h"
#include "test_support.h"

namespace omniview {
namespace {

TEST(ListenAddress, Forms) {
  for (const char* a : {"127.0.0.1:50051", "0.0.0.0:0", "[::]:65535", "localhost:1", "robot.local:50051",
                        "unix:/run/omniview.sock"}) {
    EXPECT_EQ(listen_address_problem(a), "") << a;
  }
  EXPECT_NE(listen_address_problem("").find("is empty"), std::string::npos);
  EXPECT_NE(listen_address_problem("unix:").find("no socket path"), std::string::npos);
  EXPECT_NE(listen_address_problem("127.0.0.1").find("not host:port"), std::string::npos);
  EXPECT_NE(listen_address_problem("::1:5").find("brackets"), std::string::npos);
  EXPECT_NE(listen_address_problem("[::1:5").find("not host:port"), std::string::npos);
  EXPECT_NE(listen_address_problem("[nothost]:5").find("not an IPv6 address"), std::string::npos);
  EXPECT_NE(listen_address_problem("a:").find("port must be"), std::string::npos);
  EXPECT_NE(listen_address_problem("a:-1").find("port must be"), std::string::npos);
  EXPECT_NE(listen_address_problem("a:65536").find("port must be"), std::string::npos);
  EXPECT_NE(listen_address_problem("a:123456").find("port must be"), std::string::npos);
  EXPECT_NE(listen_address_problem(":5").find("names no host"), std::string::npos);
}

constexpr char kSources[] = "sources:\n  - {name: cam, type: images}\n";  // lines 1-2

DaemonConfig parse_with(const std::string& text, ListenOptions options) {
  return parse_daemon_config(YamlReader::from_string(text, "d.yaml"), "/cfg", options);
}

TEST(ListenAddress, TheFlagWinsOverTheEnvironmentWhichWinsOverTheFile) {
  const std::string file = std::string(kSources) + "listen: 127.0.0.1:1\n";
  EXPECT_EQ(parse_with(file, {}).listen, "127.0.0.1:1");
  EXPECT_EQ(parse_with(file, {}).listen_from, "");
  const auto env = parse_with(file, {std::nullopt, "127.0.0.2:2", {}});
  EXPECT_EQ(env.listen, "127.0.0.2:2");
  EXPECT_EQ(env.listen_from, "OMNIVIEW_LISTEN");
  const auto flag = parse_with(file, {"[::1]:3", "127.0.0.2:2", {}});
  EXPECT_EQ(flag.listen, "[::1]:3");
  EXPECT_EQ(flag.listen_from, "--listen");
  EXPECT_EQ(parse_with(kSources, {}).listen, "127.0.0.1:50051");  // the default
}

TEST(ListenAddress, OptionsReadTheEnvironment) {
  ::setenv("OMNIVIEW_LISTEN", "127.0.0.9:9", 1);
  EXPECT_EQ(ListenOptions::from_environment(std::nullopt).env, "127.0.0.9:9");
  ::setenv("OMNIVIEW_LISTEN", "", 1);  // set but empty: as if unset
  EXPECT_FALSE(ListenOptions::from_environment(std::nullopt).env.has_value());
  ::unsetenv("OMNIVIEW_LISTEN");
  EXPECT_FALSE(ListenOptions::from_environment(std::nullopt).env.has_value());
  EXPECT_EQ(ListenOptions::from_environment("127.0.0.1:1").flag, "127.0.0.1:1");
}

TEST(ListenAddress, TheExposureRuleJudgesTheEffectiveAddress) {
  using testing::expect_throw_containing;
  const std::string wildcard_file = std::string(kSources) + "listen: 0.0.0.0:50051\n";  // line 3
  // The file's wildcard, replaced by a loopback flag or variable: fine.
  EXPECT_EQ(parse_with(wildcard_file, {"127.0.0.1:0", std::nullopt, {}}).listen, "127.0.0.1:0");
  EXPECT_EQ(parse_with(wildcard_file, {std::nullopt, "[::1]:0", {}}).listen, "[::1]:0");
  // The file's loopback, replaced by a wildcard: refused, and the override is named.
  const std::string loopback_file = std::string(kSources) + "listen: 127.0.0.1:50051\n";
  for (const std::string wildcard : {"0.0.0.0:1", "0:1", "[::]:1", "[0::0]:1", "[::ffff:0.0.0.0]:1"}) {
    expect_throw_containing<ConfigError>([&] { parse_with(loopback_file, {wildcard, std::nullopt, {}}); },
                                         {"--listen: '" + wildcard + "' is reachable from other machines",
                                          "neither tls nor tokens"},
                                         wildcard);
    expect_throw_containing<ConfigError>([&] { parse_with(loopback_file, {std::nullopt, wildcard, {}}); },
                                         {"OMNIVIEW_LISTEN: '" + wildcard + "' is reachable"}, wildcard);
  }
  // The file's wildcard with nothing over it: the file's line is named.
  expect_throw_containing<ConfigError>([&] { parse_with(wildcard_file, {}); }, {"d.yaml:3: listen:", "reachable"});
  // allow_insecure_remote in the file covers the flag's address too.
  EXPECT_NO_THROW(parse_with(std::string(kSources) + "allow_insecure_remote: true\n", {"0.0.0.0:0", std::nullopt, {}}));
}

TEST(ListenAddress, ABadOverrideIsBlamedOnItselfNotOnTheFile) {
  using testing::expect_throw_containing;
  const std::string file = std::string(kSources) + "listen: 127.0.0.1:50051\n";
  expect_throw_containing<ConfigError>([&] { parse_with(file, {":5", std::nullopt, {}}); }, {"--listen: ", "names no host"});
  expect_throw_containing<ConfigError>([&] { parse_with(file, {"", std::nullopt, {}}); }, {"--listen: is empty"});
  expect_throw_containing<ConfigError>([&] { parse_with(file, {"127.0.0.1", std::nullopt, {}}); },
                                       {"--listen: '127.0.0.1' is not host:port"});
  expect_throw_containing<ConfigError>([&] { parse_with(file, {std::nullopt, "x:99999", {}}); },
                                       {"OMNIVIEW_LISTEN: 'x:99999': the port must be"});
  try {
    parse_with(file, {"127.0.0.1", std::nullopt, {}});
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()).find("d.yaml"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace omniview

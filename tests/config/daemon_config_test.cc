// The daemon config: the bundled file, sources and views, limits, and that every error
// names the file, the line and the key.
#include "server/config/daemon_config.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "test_support.h"

namespace omniview {
namespace {

using testing::expect_throw_containing;

DaemonConfig parse(const std::string& text) {
  return parse_daemon_config(YamlReader::from_string(text, "d.yaml"), "/cfg");
}

void expect_error(const std::string& text, std::initializer_list<std::string> needles) {
  expect_throw_containing<ConfigError>([&] { parse(text); }, needles, text);
}

constexpr char kSources[] = "sources:\n  - {name: cam, type: images}\n";  // lines 1-2

TEST(DaemonConfig, BundledConfigParses) {
  const auto config = load_daemon_config(OMNIVIEW_SOURCE_DIR "/config/omniviewd.yaml");
  EXPECT_EQ(config.listen, "127.0.0.1:50051");
  EXPECT_FALSE(config.tls);
  EXPECT_TRUE(config.tokens.empty());
  EXPECT_EQ(config.folder, std::filesystem::path(OMNIVIEW_SOURCE_DIR "/config").lexically_normal().string());
  ASSERT_EQ(config.sources.size(), 1u);
  EXPECT_EQ(config.sources[0].name, "examples");
  EXPECT_EQ(config.sources[0].type, "images");
  EXPECT_EQ(config.sources[0].path, "sources[0]");
  // The source's own keys are kept for its factory, and point at files that exist.
  const auto rig = resolve_config_path(config.folder, config.sources[0].node["rig"].Scalar());
  EXPECT_TRUE(std::filesystem::exists(rig)) << rig;
  for (const auto& image : config.sources[0].node["images"]) {
    EXPECT_TRUE(std::filesystem::exists(resolve_config_path(config.folder, image.second.Scalar())));
  }
  ASSERT_EQ(config.views.size(), 3u);
  EXPECT_EQ(config.views[0].name, "front");
  EXPECT_EQ(config.views[1].type, ViewType::kBirdseye);
  EXPECT_EQ(config.views[2].type, ViewType::kEquirectangular);
  for (const auto& v : config.views) EXPECT_EQ(v.source, "examples");
  ASSERT_TRUE(config.reader);
  EXPECT_EQ(config.reader->file(), config.file);
  // RTSP on loopback, as the comments say.
  ASSERT_TRUE(config.rtsp);
  EXPECT_EQ(config.rtsp->listen, "127.0.0.1:8554");
}

TEST(DaemonConfig, RtspIsOffUnlessConfiguredAndItsKeysAreChecked) {
  EXPECT_FALSE(parse(kSources).rtsp);
  const auto config =
      parse(std::string(kSources) + "rtsp: {listen: 127.0.0.1:9554, quality: 60, max_bitrate_kbps: 800}\n");
  ASSERT_TRUE(config.rtsp);
  EXPECT_EQ(config.rtsp->listen, "127.0.0.1:9554");
  EXPECT_EQ(config.rtsp->quality, 60);
  EXPECT_EQ(config.rtsp->max_bitrate_kbps, 800);
  expect_error(std::string(kSources) + "rtsp: {listen: unix:/tmp/x}\n", {"d.yaml:3", "rtsp.listen", "host:port"});
  expect_error(std::string(kSources) + "rtsp: {listen: 127.0.0.1:70000}\n", {"d.yaml:3", "rtsp.listen", "0..65535"});
  expect_error(std::string(kSources) + "rtsp: {quality: 101}\n", {"d.yaml:3", "rtsp.quality"});
  expect_error(std::string(kSources) + "rtsp: {max_bitrate_kbps: 10}\n",
               {"d.yaml:3", "rtsp.max_bitrate_kbps", "50..100000"});
  expect_error(std::string(kSources) + "rtsp: {max_rate_hz: -1}\n", {"d.yaml:3", "rtsp.max_rate_hz"});
  expect_error(std::string(kSources) + "rtsp: {port: 8554}\n", {"d.yaml:3", "port"});
  // The connection caps and the idle timeout: defaults, and bounds with the key in the error.
  EXPECT_EQ(config.rtsp->max_connections, 32);
  EXPECT_EQ(config.rtsp->max_connections_per_client, 8);
  EXPECT_EQ(config.rtsp->idle_timeout_s, 20);
  const auto capped = parse(std::string(kSources) +
                            "rtsp: {max_connections: 100, max_connections_per_client: 100, idle_timeout_s: 5}\n");
  EXPECT_EQ(capped.rtsp->max_connections, 100);
  EXPECT_EQ(capped.rtsp->max_connections_per_client, 100);
  EXPECT_EQ(capped.rtsp->idle_timeout_s, 5);
  expect_error(std::string(kSources) + "rtsp: {max_connections: 0}\n", {"d.yaml:3", "rtsp.max_connections", "1 to 256"});
  expect_error(std::string(kSources) + "rtsp: {max_connections: 5000}\n", {"d.yaml:3", "rtsp.max_connections"});
  expect_error(std::string(kSources) + "rtsp: {max_connections: 4}\n",
               {"d.yaml:3", "rtsp.max_connections_per_client", "more than rtsp.max_connections (4)"});
  expect_error(std::string(kSources) + "rtsp: {idle_timeout_s: 0}\n", {"d.yaml:3", "rtsp.idle_timeout_s", "1 to 3600"});
  expect_error(std::string(kSources) + "rtsp: yes\n", {"d.yaml:3", "rtsp"});
  // The exposure rule, as for `listen`: others can reach it, and nothing guards it.
  expect_error(std::string(kSources) + "rtsp: {listen: 0.0.0.0:8554}\n",
               {"d.yaml:3", "rtsp.listen", "reachable from other machines"});
}

TEST(DaemonConfig, DefaultsAndMinimalConfig) {
  const auto config = parse(kSources);
  EXPECT_EQ(config.listen, "127.0.0.1:50051");
  EXPECT_EQ(config.file, "d.yaml");
  EXPECT_EQ(config.folder, "/cfg");
  EXPECT_EQ(config.limits.max_views, Limits{}.max_views);
  EXPECT_TRUE(config.views.empty());
}

TEST(DaemonConfig, ViewsDefaultToTheFirstSource) {
  const auto config = parse(std::string(kSources) +
                            "  - {name: other, type: replay}\n"
                            "views:\n"
                            "  - {name: a, type: perspective}\n"
                            "  - {name: b, type: fisheye, source: other}\n");
  ASSERT_EQ(config.views.size(), 2u);
  EXPECT_EQ(config.views[0].source, "cam");
  EXPECT_EQ(config.views[1].source, "other");
  EXPECT_EQ(config.sources[1].type, "replay");
}

TEST(DaemonConfig, SourceKeysOfTheTypeAreNotChecked) {
  const auto config = parse("sources:\n  - {name: s, type: anything, whatever: [1, 2], rate_hz: fast}\n");
  EXPECT_EQ(config.sources[0].node["whatever"].size(), 2u);
}

TEST(DaemonConfig, TopLevelErrors) {
  expect_error(std::string(kSources) + "listn: 1.2.3.4:5\n", {"d.yaml:3: listn: unknown key", "listen"});
  expect_error("listen: 127.0.0.1:1\n", {"d.yaml:1: ", "missing required key 'sources'"});
  expect_error("- a\n- b\n", {"d.yaml:1: ", "expected a map"});
  expect_error("sources: []\n", {"d.yaml:1: sources: expected a list of at least one"});
  expect_error(std::string(kSources) + "allow_insecure_remote: sure\n",
               {"d.yaml:3: allow_insecure_remote: expected true or false"});
  expect_error(std::string(kSources) + "sources: []\n", {"d.yaml:3: sources: key given twice"});
}

TEST(DaemonConfig, SourceErrors) {
  expect_error("sources:\n  - {name: cam}\n", {"d.yaml:2: sources[0]: missing required key 'type'"});
  expect_error("sources:\n  - type: images\n", {"d.yaml:2: sources[0]: missing required key 'name'"});
  expect_error("sources:\n  - cam\n", {"d.yaml:2: sources[0]: expected a map"});
  expect_error("sources:\n  - {name: '', type: images}\n", {"d.yaml:2: sources[0].name: is empty"});
  expect_error(std::string(kSources) + "  - {name: cam, type: replay}\n",
               {"d.yaml:3: sources[1].name: 'cam' is already the name of sources[0]"});
}

TEST(DaemonConfig, ViewErrors) {
  const std::string base = std::string(kSources) + "views:\n";  // views from line 4
  expect_error(base + "  - {name: a, type: perspective}\n  - {name: a, type: birdseye}\n",
               {"d.yaml:5: views[1].name: 'a' is already the name of views[0]"});
  expect_error(base + "  - {name: a, type: perspective}\n  - {name: b, type: birdseye,\n     source: nope}\n",
               {"d.yaml:6: views[1].source: no source is named 'nope' (sources: cam)"});
  expect_error(base + "  - {name: a, type: perspective, hfov_deg: 200}\n", {"d.yaml:4: views[0]", "hfov"});
  expect_error(base + "  - {name: a, type: perspective, colour: red}\n",
               {"d.yaml:4: views[0].colour: unknown key"});
  expect_error(base + "  - {name: a, type: sphere}\n", {"d.yaml:4: views[0].type:"});
  expect_error("sources:\n  - {name: cam, type: images}\nviews: {name: a}\n", {"d.yaml:3: views: expected a list"});
  expect_error(base + "  - {name: a, type: perspective, depth: lidar}\n", {"d.yaml:4: views[0].depth:", "unknown depth 'lidar'"});
}

TEST(DaemonConfig, ViewsMustStayWithinTheLimits) {
  const std::string limits = "limits: {max_view_pixels: 10000, max_views: 2}\n";  // line 3
  const std::string views = std::string(kSources) + limits + "views:\n";           // views from line 5
  EXPECT_NO_THROW(parse(views + "  - {name: a, type: perspective, width: 100, height: 100}\n"));
  expect_error(views + "  - {name: a, type: perspective, width: 100, height: 100}\n"
                       "  - {name: b, type: perspective, width: 200, height: 100}\n",
               {"d.yaml:6: views[1]: view 'b' is 200x100 = 20000 pixels, more than limits.max_view_pixels (10000)"});
  expect_error(views + "  - {name: a, type: perspective, width: 10, height: 10}\n"
                       "  - {name: b, type: perspective, width: 10, height: 10}\n"
                       "  - {name: c, type: perspective, width: 10, height: 10}\n",
               {"d.yaml:7: views: 3 views, more than limits.max_views (2)"});
  // The default limit: 4096 x 4096.
  expect_error(std::string(kSources) + "views:\n  - {name: a, type: perspective, width: 8192, height: 4096}\n",
               {"d.yaml:4: views[0]:", "limits.max_view_pixels (16777216)"});
}

TEST(DaemonConfig, Limits) {
  const auto config = parse(std::string(kSources) +
                            "limits: {max_view_pixels: 1000000, max_views: 4, max_streams_per_client: 2,\n"
                            "         max_streams: 3, max_message_bytes: 1048576, max_rate_hz: 12.5,\n"
                            "         record_queue_frame_sets: 5, record_queue_mb: 64}\n");
  EXPECT_EQ(config.limits.max_view_pixels, 1000000);
  EXPECT_EQ(config.limits.max_views, 4);
  EXPECT_EQ(config.limits.max_streams_per_client, 2);
  EXPECT_EQ(config.limits.max_streams, 3);
  EXPECT_EQ(config.limits.max_message_bytes, 1048576);
  EXPECT_EQ(config.limits.max_rate_hz, 12.5);
  EXPECT_EQ(config.limits.record_queue_frame_sets, 5);
  EXPECT_EQ(config.limits.record_queue_mb, 64);

  const std::string base = std::string(kSources) + "limits:\n";  // limit keys on line 4
  expect_error(base + "  max_views: 0\n", {"d.yaml:4: limits.max_views: must be from 1 to 1024, got 0"});
  expect_error(base + "  record_queue_frame_sets: 0\n",
               {"d.yaml:4: limits.record_queue_frame_sets: must be from 1 to 10000, got 0"});
  expect_error(base + "  max_streams: -3\n", {"d.yaml:4: limits.max_streams: must be from 1"});
  expect_error(base + "  max_view_pixels: 1e12\n", {"d.yaml:4: limits.max_view_pixels: expected an integer"});
  expect_error(base + "  max_view_pixels: 300000000\n", {"d.yaml:4: limits.max_view_pixels: must be from 1 to 268435456"});
  expect_error(base + "  max_message_bytes: 1000\n", {"d.yaml:4: limits.max_message_bytes: must be from 65536"});
  expect_error(base + "  max_rate_hz: 0\n", {"d.yaml:4: limits.max_rate_hz: must be above 0"});
  expect_error(base + "  max_rate_hz: 5000\n", {"d.yaml:4: limits.max_rate_hz: must be above 0 and at most 1000"});
  expect_error(base + "  max_streams: 4\n  max_streams_per_client: 5\n",
               {"d.yaml:5: limits.max_streams_per_client: 5 is more than limits.max_streams (4)"});
  expect_error(base + "  max_stream: 4\n", {"d.yaml:4: limits.max_stream: unknown key"});
  expect_error(std::string(kSources) + "limits: 5\n", {"d.yaml:3: limits: expected a map"});
}

TEST(DaemonConfig, ListenAddressForm) {
  const std::string base = std::string(kSources);
  expect_error(base + "listen: 127.0.0.1\n", {"d.yaml:3: listen: '127.0.0.1' is not host:port"});
  expect_error(base + "listen: 127.0.0.1:http\n", {"d.yaml:3: listen:", "port must be a number"});
  expect_error(base + "listen: 127.0.0.1:70000\n", {"d.yaml:3: listen:", "port must be a number from 0 to 65535"});
  expect_error(base + "listen: '::1:5'\n", {"d.yaml:3: listen:", "brackets"});
  expect_error(base + "listen: ':5'\n", {"d.yaml:3: listen:", "names no host"});
  expect_error(base + "listen: [1, 2]\n", {"d.yaml:3: listen: expected a string"});
  EXPECT_EQ(parse(base + "listen: '[::1]:0'\n").listen, "[::1]:0");
  testing::TempDir closed;  // a folder only its owner can enter
  std::filesystem::permissions(closed.path(), std::filesystem::perms::owner_all, std::filesystem::perm_options::replace);
  const std::string socket = "unix:" + (closed / "omniview.sock");
  EXPECT_EQ(parse(base + "listen: " + socket + "\n").listen, socket);
  // /tmp lets every user in: the exposure rule (server/exposure) refuses it without tls and tokens.
  expect_error(base + "listen: unix:/tmp/omniview.sock\n", {"d.yaml:3: listen:", "folder '/tmp'"});
}

TEST(DaemonConfig, LoadsFromAFileAndResolvesAgainstItsFolder) {
  testing::TempDir dir;
  dir.write("secrets/op.token", "s3cret-operator\n");
  const auto file = dir.write("conf/d.yaml",
                              "tokens:\n  - {role: operator, token_file: ../secrets/op.token}\n" + std::string(kSources));
  const auto config = load_daemon_config(file);
  EXPECT_EQ(config.file, file);
  EXPECT_EQ(config.folder, (dir.path() / "conf").string());
  ASSERT_EQ(config.tokens.size(), 1u);
  EXPECT_EQ(config.tokens[0].token, "s3cret-operator");
  EXPECT_EQ(config.tokens[0].role, Role::kOperator);
  EXPECT_EQ(config.tokens[0].label, "tokens[0] (" + (dir.path() / "secrets/op.token").string() + ")");
  expect_throw_containing<ConfigError>([&] { load_daemon_config(dir / "conf/none.yaml"); }, {"none.yaml: cannot open"});
}

TEST(DaemonConfig, ResolvesPaths) {
  EXPECT_EQ(resolve_config_path("/etc/omniview", "a.crt"), "/etc/omniview/a.crt");
  EXPECT_EQ(resolve_config_path("/etc/omniview", "../x/a.crt"), "/etc/x/a.crt");
  EXPECT_EQ(resolve_config_path("/etc/omniview", "/abs/a.crt"), "/abs/a.crt");
  EXPECT_EQ(resolve_config_path("", "a.crt"), "a.crt");
}

}  // namespace
}  // namespace omniview

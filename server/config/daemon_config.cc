// The daemon's config file, checked whole before anything starts: a daemon that comes up
// half-configured (a view silently dropped, auth silently off) is worse than one that
// refuses with a message naming the line to fix.
#include "server/config/daemon_config.h"

#include <filesystem>

#include "server/config/config_parts.h"

namespace omniview {
namespace {

// What a remote peer could do that the config does not prevent; empty when TLS and tokens
// are both on.
std::string remote_exposure(const DaemonConfig& config) {
  const bool tls = config.tls.has_value();
  const bool tokens = !config.tokens.empty();
  if (tls && tokens) return "";
  if (!tls && !tokens) {
    return "there is neither tls nor tokens: anyone who can reach it can watch the cameras and change the views";
  }
  if (!tls) return "there is no tls: the tokens and the camera images cross the network in plaintext";
  return "there are no tokens: anyone who can reach it can watch the cameras and change the views";
}

void check_exposure(const YamlReader& r, const DaemonConfig& config) {
  if (config.allow_insecure_remote || is_loopback_address(config.listen)) return;
  const auto exposure = remote_exposure(config);
  if (exposure.empty()) return;
  const YAML::Node listen = r.root()["listen"];
  r.fail(listen ? listen : r.root(), "listen",
         "'" + config.listen + "' is reachable from other machines, but " + exposure +
             ". Configure tls and tokens, or listen on 127.0.0.1, or set allow_insecure_remote: true "
             "if the network is trusted");
}

}  // namespace

std::string resolve_config_path(const std::string& folder, const std::string& path) {
  const std::filesystem::path p(path);
  if (p.is_absolute() || folder.empty()) return path;
  return (std::filesystem::path(folder) / p).lexically_normal().string();
}

DaemonConfig parse_daemon_config(const YamlReader& reader, const std::string& folder) {
  using namespace config_parts;
  const auto shared = std::make_shared<const YamlReader>(reader);
  const YamlReader& r = *shared;
  const YAML::Node root = r.root();
  if (!root.IsMap()) r.fail(root, "", "expected a map with listen, sources, views, ...");
  r.expect_keys(root, "", {"listen", "tls", "tokens", "allow_insecure_remote", "limits", "sources", "views",
                          "robot_models", "views_file"});

  DaemonConfig config;
  config.file = r.file();
  config.folder = folder;
  config.reader = shared;
  if (const YAML::Node listen = root["listen"]) {
    config.listen = r.text(listen, "listen");
    if (const auto problem = listen_address_problem(config.listen); !problem.empty()) r.fail(listen, "listen", problem);
  }
  if (root["tls"] && !root["tls"].IsNull()) config.tls = parse_tls(r, root["tls"], folder);
  config.tokens = parse_tokens(r, root["tokens"], folder);
  if (const YAML::Node allow = root["allow_insecure_remote"]) {
    config.allow_insecure_remote = r.boolean(allow, "allow_insecure_remote");
  }
  config.limits = parse_limits(r, root["limits"]);
  config.sources = parse_sources(r, root["sources"]);
  config.views = parse_daemon_views(r, root["views"], config.sources, config.limits);
  if (const YAML::Node views_file = root["views_file"]) {
    config.views_file = resolve_config_path(folder, r.text(views_file, "views_file"));
    apply_views_file(r, views_file, config.views_file, config.sources, config.limits, config.views);
  }
  config.robot_models = parse_robot_models(r, root["robot_models"], config.sources, folder);
  check_exposure(r, config);
  return config;
}

DaemonConfig load_daemon_config(const std::string& path) {
  const auto reader = YamlReader::from_file(path);
  std::error_code ec;
  auto folder = std::filesystem::absolute(path, ec).parent_path().lexically_normal();
  if (ec) folder = std::filesystem::path(path).parent_path();
  return parse_daemon_config(reader, folder.string());
}

}  // namespace omniview

// The daemon's config file, checked whole before anything starts: a daemon that comes up
// half-configured (a view silently dropped, auth silently off) is worse than one that
// refuses with a message naming the line to fix.
#include "server/config/daemon_config.h"

#include <cstdlib>
#include <filesystem>

#include "server/config/config_parts.h"

namespace omniview {
namespace {

constexpr char kListenEnv[] = "OMNIVIEW_LISTEN";

// A --listen or OMNIVIEW_LISTEN value replaces the file's; its mistakes are its own.
void apply_listen_override(DaemonConfig& config, const std::optional<std::string>& value, const std::string& from) {
  if (!value) return;
  if (const auto problem = listen_address_problem(*value); !problem.empty()) throw ConfigError(from + ": " + problem);
  config.listen = *value;
  config.listen_from = from;
}

}  // namespace

std::string resolve_config_path(const std::string& folder, const std::string& path) {
  const std::filesystem::path p(path);
  if (p.is_absolute() || folder.empty()) return path;
  return (std::filesystem::path(folder) / p).lexically_normal().string();
}

ListenOptions ListenOptions::from_environment(std::optional<std::string> flag) {
  ListenOptions options;
  options.flag = std::move(flag);
  if (const char* env = std::getenv(kListenEnv); env && *env) options.env = env;
  return options;
}

void check_listen_exposure(const DaemonConfig& config, const HostResolver& resolve) {
  const EndpointGuards endpoint{config.listen, config.tls.has_value(), !config.tokens.empty(),
                                config.allow_insecure_remote};
  const std::string refusal = exposure_refusal(endpoint, resolve);
  if (refusal.empty()) return;
  if (!config.listen_from.empty()) throw ConfigError(config.listen_from + ": " + refusal);
  if (!config.reader) throw ConfigError(config.file + ": listen: " + refusal);
  const YamlReader& r = *config.reader;
  const YAML::Node listen = r.root()["listen"];
  r.fail(listen ? listen : r.root(), "listen", refusal);
}

namespace {

// The rule for a second listener (`block`.listen: rtsp, web): the same guards as the gRPC
// address, refused at the block's listen key.
void check_block_exposure(const DaemonConfig& config, const std::string& block, const std::string& listen,
                          const HostResolver& resolve) {
  const EndpointGuards endpoint{listen, config.tls.has_value(), !config.tokens.empty(), config.allow_insecure_remote};
  const std::string refusal = exposure_refusal(endpoint, resolve);
  if (refusal.empty()) return;
  const std::string key = block + ".listen";
  if (!config.reader) throw ConfigError(config.file + ": " + key + ": " + refusal);
  const YamlReader& r = *config.reader;
  const YAML::Node node = r.root()[block];
  const YAML::Node at = node && node.IsMap() && node["listen"] ? node["listen"] : (node ? node : r.root());
  r.fail(at, key, refusal);
}

}  // namespace

void check_rtsp_exposure(const DaemonConfig& config, const HostResolver& resolve) {
  if (config.rtsp) check_block_exposure(config, "rtsp", config.rtsp->listen, resolve);
}

void check_web_exposure(const DaemonConfig& config, const HostResolver& resolve) {
  if (config.web.enabled) check_block_exposure(config, "web", config.web.listen, resolve);
}

DaemonConfig parse_daemon_config(const YamlReader& reader, const std::string& folder, const ListenOptions& options) {
  using namespace config_parts;
  const auto shared = std::make_shared<const YamlReader>(reader);
  const YamlReader& r = *shared;
  const YAML::Node root = r.root();
  if (!root.IsMap()) r.fail(root, "", "expected a map with listen, sources, views, ...");
  r.expect_keys(root, "", {"listen", "tls", "tokens", "allow_insecure_remote", "limits", "sources", "views",
                          "robot_models", "views_file", "rtsp", "web", "blackbox"});

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
  config.web = parse_web(r, root["web"], folder);
  apply_listen_override(config, options.env, kListenEnv);
  apply_listen_override(config, options.flag, "--listen");
  if (const YAML::Node rtsp = root["rtsp"]; rtsp && !rtsp.IsNull()) config.rtsp = parse_rtsp(r, rtsp, config.limits);
  if (const YAML::Node box = root["blackbox"]; box && !box.IsNull()) config.blackbox = parse_blackbox(r, box, folder);
  check_listen_exposure(config, options.resolve);
  check_rtsp_exposure(config, options.resolve);
  check_web_exposure(config, options.resolve);
  return config;
}

DaemonConfig load_daemon_config(const std::string& path, const ListenOptions& listen) {
  const auto reader = YamlReader::from_file(path);
  std::error_code ec;
  auto folder = std::filesystem::absolute(path, ec).parent_path().lexically_normal();
  if (ec) folder = std::filesystem::path(path).parent_path();
  return parse_daemon_config(reader, folder.string(), listen);
}

}  // namespace omniview

// The pieces parse_daemon_config() is assembled from, one file each so every check stays
// short enough to read. Internal to omniview_config; every function throws ConfigError
// through `reader` ("file:line: key: message").
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "core/io/yaml_reader.h"
#include "server/config/daemon_config.h"

namespace omniview::config_parts {

Limits parse_limits(const YamlReader& reader, const YAML::Node& node);
TlsConfig parse_tls(const YamlReader& reader, const YAML::Node& node, const std::string& folder);
std::vector<TokenConfig> parse_tokens(const YamlReader& reader, const YAML::Node& node, const std::string& folder);
std::vector<SourceEntry> parse_sources(const YamlReader& reader, const YAML::Node& node);
std::vector<ViewSpec> parse_daemon_views(const YamlReader& reader, const YAML::Node& node,
                                         const std::vector<SourceEntry>& sources, const Limits& limits);

// Reads `file` (a `views:` list, as `omniview views save` writes it) if it exists and lays
// its views over `views`: a view of the same name is replaced, others are added. Errors
// name `file` and its line; the total must stay within limits.max_views.
void apply_views_file(const YamlReader& config_reader, const YAML::Node& node, const std::string& file,
                      const std::vector<SourceEntry>& sources, const Limits& limits, std::vector<ViewSpec>& views);

BlackBoxConfig parse_blackbox(const YamlReader& reader, const YAML::Node& node, const std::string& folder);
RtspConfig parse_rtsp(const YamlReader& reader, const YAML::Node& node, const Limits& limits);
WebConfig parse_web(const YamlReader& reader, const YAML::Node& node, const std::string& folder);

std::vector<RobotModelEntry> parse_robot_models(const YamlReader& reader, const YAML::Node& node,
                                                const std::vector<SourceEntry>& sources, const std::string& folder);

}  // namespace omniview::config_parts

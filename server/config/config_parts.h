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

std::vector<RobotModelEntry> parse_robot_models(const YamlReader& reader, const YAML::Node& node,
                                                const std::vector<SourceEntry>& sources, const std::string& folder);

}  // namespace omniview::config_parts

// Source types by name, so the daemon config can say `type: images` (or spot, insta360,
// ...) and each adapter registers itself without the server knowing it.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "core/io/yaml_reader.h"
#include "server/source/source.h"

namespace omniview {

// Everything a factory gets: the source's name, its YAML map (to read with `reader`, so
// errors name file, line and key), and the config file's folder for relative paths.
struct SourceConfig {
  std::string name;
  const YamlReader* reader = nullptr;
  YAML::Node node;
  std::string path;    // YAML path of `node`, for messages (e.g. "sources[0]")
  std::string folder;  // relative paths resolve against it
};

using SourceFactory = std::function<std::unique_ptr<Source>(const SourceConfig&)>;

// Registers `type` (at start-up: the daemon calls each adapter's register function, since
// static initialisers in a static library are dropped by the linker).
void register_source_type(const std::string& type, const std::string& help, SourceFactory factory);

// Throws ConfigError naming the file, line and key for an unknown type or bad settings.
std::unique_ptr<Source> make_source(const std::string& type, const SourceConfig& config);

// "type: help" lines, for --help and error messages.
std::vector<std::pair<std::string, std::string>> source_types();

}  // namespace omniview

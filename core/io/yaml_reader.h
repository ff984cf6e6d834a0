// Reading our YAML files with errors a person can act on: every message names the
// file, the line and the key path ("rig.yaml:14: cameras[1].intrinsics: ...").
#pragma once

#include <initializer_list>
#include <stdexcept>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "core/geometry/pose.h"

namespace omniview {

struct ConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class YamlReader {
 public:
  // Parses `path`; throws ConfigError for a missing file or a YAML syntax error.
  static YamlReader from_file(const std::string& path);
  // Parses `text`; `name` stands for the file in messages.
  static YamlReader from_string(const std::string& text, const std::string& name);

  const YAML::Node& root() const { return root_; }
  const std::string& file() const { return file_; }

  // "file:line: path: message" for `node` (line omitted when unknown).
  [[noreturn]] void fail(const YAML::Node& node, const std::string& path, const std::string& message) const;

  // Fails unless `node` is a map whose keys are all in `allowed` (catches typos).
  void expect_keys(const YAML::Node& node, const std::string& path,
                   std::initializer_list<const char*> allowed) const;
  YAML::Node required(const YAML::Node& map, const std::string& key, const std::string& path) const;

  double number(const YAML::Node& node, const std::string& path) const;
  int integer(const YAML::Node& node, const std::string& path) const;
  std::string text(const YAML::Node& node, const std::string& path) const;
  bool boolean(const YAML::Node& node, const std::string& path) const;
  std::vector<double> numbers(const YAML::Node& node, const std::string& path) const;
  // Exactly n numbers.
  std::vector<double> numbers(const YAML::Node& node, const std::string& path, size_t n) const;

  // A rigid transform: a 4x4 matrix (list of 4 rows, as kalibr writes), or a map with
  // `xyz` and one of `ypr_deg` [yaw, pitch, roll] or `quat_xyzw`.
  Pose pose(const YAML::Node& node, const std::string& path) const;

 private:
  YamlReader(YAML::Node root, std::string file) : root_(std::move(root)), file_(std::move(file)) {}
  YAML::Node root_;
  std::string file_;
};

}  // namespace omniview

#include "server/sources/source_config_helpers.h"

#include <cmath>
#include <filesystem>

namespace omniview {

std::string config_path(const SourceConfig& config, const char* key) {
  const YamlReader& r = *config.reader;
  const std::string text = r.text(r.required(config.node, key, config.path), config.path + "." + key);
  const std::filesystem::path path(text);
  return path.is_absolute() || config.folder.empty() ? text : (std::filesystem::path(config.folder) / path).string();
}

double positive_number(const SourceConfig& config, const char* key, double fallback) {
  const YAML::Node node = config.node[key];
  if (!node) return fallback;
  const double value = config.reader->number(node, config.path + "." + key);
  if (!(value > 0) || !std::isfinite(value)) config.reader->fail(node, config.path + "." + key, "must be > 0");
  return value;
}

std::shared_ptr<const Rig> load_config_rig(const SourceConfig& config) {
  const YamlReader& r = *config.reader;
  const std::string path = config_path(config, "rig");
  const std::string frame = config.node["rig_frame"] ? r.text(config.node["rig_frame"], config.path + ".rig_frame")
                                                     : "base_link";
  Pose pose = Pose::Identity();
  if (const YAML::Node p = config.node["rig_pose"]) {
    const std::string key = config.path + ".rig_pose";
    // Like the CLI's --rig-pose "x y z yaw pitch roll"; or any pose the reader accepts.
    if (p.IsSequence() && p.size() == 6) {
      const auto v = r.numbers(p, key, 6);
      pose = make_pose(Vec3(v[0], v[1], v[2]), v[3] * M_PI / 180, v[4] * M_PI / 180, v[5] * M_PI / 180);
    } else {
      pose = r.pose(p, key);
    }
  }
  try {
    return std::make_shared<const Rig>(load_rig(path, frame, pose));
  } catch (const ConfigError&) {
    throw;  // already names the rig file and line
  } catch (const std::exception& e) {
    r.fail(config.node["rig"], config.path + ".rig", "cannot load rig '" + path + "': " + e.what());
  }
}

}  // namespace omniview

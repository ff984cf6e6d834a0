#include "spot_adapter/source/spot_settings.h"

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <fstream>
#include <set>
#include <sstream>

#include "server/sources/source_config_helpers.h"
#include "spot_adapter/client/credentials.h"
#include "spot_adapter/client/spot_error.h"

namespace omniview::spot {

const std::vector<std::string>& default_body_cameras() {
  static const std::vector<std::string> cameras = {"frontleft_fisheye_image", "frontright_fisheye_image",
                                                   "left_fisheye_image", "right_fisheye_image", "back_fisheye_image"};
  return cameras;
}

namespace {

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string choice(const SourceConfig& config, const char* key, const std::string& fallback,
                   std::initializer_list<const char*> allowed) {
  const YAML::Node node = config.node[key];
  if (!node) return fallback;
  const std::string path = config.path + "." + key;
  const std::string value = config.reader->text(node, path);
  std::string list;
  for (const char* a : allowed) {
    if (value == a) return value;
    list += (list.empty() ? "" : ", ") + std::string(a);
  }
  config.reader->fail(node, path, "'" + value + "' is not one of: " + list);
}

}  // namespace

SpotSettings parse_spot_settings(const SourceConfig& config) {
  const YamlReader& r = *config.reader;
  r.expect_keys(config.node, config.path,
                {"name", "type", "robot", "ca_file", "credentials_file", "cameras", "rate_hz", "image_format",
                 "jpeg_quality", "pixel_format", "timeout_s", "requests_in_flight", "point_cloud_source"});
  SpotSettings s;
  const YAML::Node robot = r.required(config.node, "robot", config.path);
  try {
    s.address = parse_robot_address(r.text(robot, config.path + ".robot"));
  } catch (const std::invalid_argument& e) {
    r.fail(robot, config.path + ".robot", e.what());
  }

  const std::string ca = config_path(config, "ca_file");
  s.ca_pem = read_file(ca);
  if (s.ca_pem.find("-----BEGIN CERTIFICATE-----") == std::string::npos) {
    r.fail(config.node["ca_file"], config.path + ".ca_file",
           "'" + ca + "' is missing or holds no PEM certificate (the CA the robot's certificates chain to)");
  }

  if (config.node["credentials_file"]) {
    s.credentials_file = config_path(config, "credentials_file");
    const std::string key = config.path + ".credentials_file";
    try {
      load_credentials(s.credentials_file);  // the keys are there (read again at every login)
    } catch (const SpotError& e) {
      r.fail(config.node["credentials_file"], key, e.what());
    }
    namespace fs = std::filesystem;
    const auto perms = fs::status(s.credentials_file).permissions();
    if ((perms & (fs::perms::group_read | fs::perms::others_read)) != fs::perms::none) {
      std::cerr << "omniviewd: warning: " << r.file() << ": " << key << ": '" << s.credentials_file
                << "' is readable by other users; the robot's password belongs to the daemon's user only "
                   "(chmod 600)\n";
    }
  } else if (!std::getenv(kUsernameEnv) || !std::getenv(kPasswordEnv)) {
    r.fail(config.node, config.path,
           std::string("no robot credentials: set `credentials_file`, or the environment variables ") + kUsernameEnv +
               " and " + kPasswordEnv);
  }

  if (const YAML::Node cams = config.node["cameras"]) {
    const std::string path = config.path + ".cameras";
    if (!cams.IsSequence() || cams.size() == 0) r.fail(cams, path, "expected a list of image source names");
    std::set<std::string> seen;
    for (size_t i = 0; i < cams.size(); ++i) {
      const std::string name = r.text(cams[i], path + "[" + std::to_string(i) + "]");
      if (!seen.insert(name).second) r.fail(cams[i], path, "'" + name + "' is listed twice");
      s.cameras.push_back(name);
    }
  } else {
    s.cameras = default_body_cameras();
  }

  s.rate_hz = positive_number(config, "rate_hz", 15);
  if (s.rate_hz > 30) r.fail(config.node["rate_hz"], config.path + ".rate_hz", "must be <= 30 (Spot's cameras give ~15)");
  s.jpeg = choice(config, "image_format", "jpeg", {"jpeg", "raw"}) == "jpeg";
  s.prefer_rgb = choice(config, "pixel_format", "greyscale", {"greyscale", "grayscale", "rgb"}) == "rgb";
  if (const YAML::Node q = config.node["jpeg_quality"]) {
    s.jpeg_quality = r.integer(q, config.path + ".jpeg_quality");
    if (s.jpeg_quality < 1 || s.jpeg_quality > 100) r.fail(q, config.path + ".jpeg_quality", "must be in 1..100");
  }
  const double timeout = positive_number(config, "timeout_s", 2);
  if (timeout > 60) r.fail(config.node["timeout_s"], config.path + ".timeout_s", "must be <= 60 s");
  s.timeout = std::chrono::milliseconds(static_cast<int64_t>(timeout * 1000));
  if (const YAML::Node n = config.node["requests_in_flight"]) {
    s.requests_in_flight = r.integer(n, config.path + ".requests_in_flight");
    if (s.requests_in_flight < 1 || s.requests_in_flight > 4) {
      r.fail(n, config.path + ".requests_in_flight", "must be in 1..4");
    }
  }
  if (const YAML::Node n = config.node["point_cloud_source"]) {
    s.point_cloud_source = r.text(n, config.path + ".point_cloud_source");
    if (s.point_cloud_source.empty()) {
      r.fail(n, config.path + ".point_cloud_source", "expected auto, none, or the name of the robot's point-cloud source");
    }
  }
  return s;
}

}  // namespace omniview::spot

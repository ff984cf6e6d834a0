#include "core/io/yaml_reader.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace omniview {

YamlReader YamlReader::from_file(const std::string& path) {
  // An ifstream opens a directory without complaint and then reads nothing, which would
  // surface as a confusing "expected a map" about an empty document.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw ConfigError(path + ": is a directory, not a file");
  std::ifstream in(path);
  if (!in) throw ConfigError(path + ": cannot open file");
  std::stringstream ss;
  ss << in.rdbuf();
  return from_string(ss.str(), path);
}

YamlReader YamlReader::from_string(const std::string& text, const std::string& name) {
  try {
    return YamlReader(YAML::Load(text), name);
  } catch (const YAML::Exception& e) {
    throw ConfigError(name + ":" + std::to_string(e.mark.line + 1) + ": YAML syntax error: " + e.msg);
  }
}

void YamlReader::fail(const YAML::Node& node, const std::string& path, const std::string& message) const {
  std::ostringstream os;
  os << file_;
  if (node.IsDefined() && node.Mark().line >= 0) os << ":" << node.Mark().line + 1;
  os << ": " << (path.empty() ? "" : path + ": ") << message;
  throw ConfigError(os.str());
}

void YamlReader::expect_keys(const YAML::Node& node, const std::string& path,
                             std::initializer_list<const char*> allowed) const {
  if (!node.IsMap()) fail(node, path, "expected a map");
  std::map<std::string, int> seen;  // key -> line
  for (const auto& kv : node) {
    const auto key = kv.first.Scalar();
    const std::string key_path = path.empty() ? key : path + "." + key;
    bool ok = false;
    for (const char* a : allowed) ok = ok || key == a;
    if (!ok) {
      std::string list;
      for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      fail(kv.first, key_path, "unknown key (expected one of: " + list + ")");
    }
    // yaml-cpp keeps duplicate keys and node[key] returns the first: an edit to the second
    // copy would silently do nothing.
    const auto [it, inserted] = seen.emplace(key, kv.first.Mark().line + 1);
    if (!inserted) fail(kv.first, key_path, "key given twice (first on line " + std::to_string(it->second) + ")");
  }
}

YAML::Node YamlReader::required(const YAML::Node& map, const std::string& key, const std::string& path) const {
  if (!map.IsMap()) fail(map, path, "expected a map");
  YAML::Node n = map[key];
  if (!n.IsDefined() || n.IsNull()) fail(map, path, "missing required key '" + key + "'");
  return n;
}

double YamlReader::number(const YAML::Node& node, const std::string& path) const {
  if (!node.IsScalar()) fail(node, path, "expected a number");
  double x;
  try {
    x = node.as<double>();
  } catch (const YAML::Exception&) {
    fail(node, path, "expected a number, got '" + node.Scalar() + "'");
  }
  if (!std::isfinite(x)) fail(node, path, "must be finite, got '" + node.Scalar() + "'");
  return x;
}

int YamlReader::integer(const YAML::Node& node, const std::string& path) const {
  if (!node.IsScalar()) fail(node, path, "expected an integer");
  try {
    return node.as<int>();
  } catch (const YAML::Exception&) {
    fail(node, path, "expected an integer, got '" + node.Scalar() + "'");
  }
}

std::string YamlReader::text(const YAML::Node& node, const std::string& path) const {
  if (!node.IsScalar()) fail(node, path, "expected a string");
  return node.Scalar();
}

bool YamlReader::boolean(const YAML::Node& node, const std::string& path) const {
  if (!node.IsScalar()) fail(node, path, "expected true or false");
  try {
    return node.as<bool>();
  } catch (const YAML::Exception&) {
    fail(node, path, "expected true or false, got '" + node.Scalar() + "'");
  }
}

std::vector<double> YamlReader::numbers(const YAML::Node& node, const std::string& path) const {
  if (!node.IsSequence()) fail(node, path, "expected a list of numbers");
  std::vector<double> out;
  for (size_t i = 0; i < node.size(); ++i) out.push_back(number(node[i], path + "[" + std::to_string(i) + "]"));
  return out;
}

std::vector<double> YamlReader::numbers(const YAML::Node& node, const std::string& path, size_t n) const {
  auto v = numbers(node, path);
  if (v.size() != n) {
    fail(node, path, "expected " + std::to_string(n) + " numbers, got " + std::to_string(v.size()));
  }
  return v;
}

Pose YamlReader::pose(const YAML::Node& node, const std::string& path) const {
  if (node.IsSequence()) {
    if (node.size() != 4) fail(node, path, "a transform matrix needs 4 rows, got " + std::to_string(node.size()));
    Mat4 m;
    for (int r = 0; r < 4; ++r) {
      const auto row = numbers(node[r], path + "[" + std::to_string(r) + "]", 4);
      for (int c = 0; c < 4; ++c) m(r, c) = row[c];
    }
    try {
      return pose_from_matrix(m, path);
    } catch (const std::invalid_argument& e) {
      fail(node, "", e.what());
    }
  }
  if (!node.IsMap()) fail(node, path, "expected a 4x4 matrix or a map with xyz and ypr_deg or quat_xyzw");
  expect_keys(node, path, {"xyz", "ypr_deg", "quat_xyzw"});
  Vec3 t = Vec3::Zero();
  if (node["xyz"]) {
    const auto v = numbers(node["xyz"], path + ".xyz", 3);
    t = Vec3(v[0], v[1], v[2]);
  }
  if (node["ypr_deg"] && node["quat_xyzw"]) fail(node, path, "give either ypr_deg or quat_xyzw, not both");
  Pose T = Pose::Identity();
  if (node["ypr_deg"]) {
    const auto a = numbers(node["ypr_deg"], path + ".ypr_deg", 3);
    T = make_pose(t, a[0] * M_PI / 180, a[1] * M_PI / 180, a[2] * M_PI / 180);
  } else if (node["quat_xyzw"]) {
    const auto q = numbers(node["quat_xyzw"], path + ".quat_xyzw", 4);
    Eigen::Quaterniond quat(q[3], q[0], q[1], q[2]);
    if (std::abs(quat.norm() - 1) > 1e-3) {
      fail(node["quat_xyzw"], path + ".quat_xyzw", "quaternion must have unit length, has " + std::to_string(quat.norm()));
    }
    T.linear() = quat.normalized().toRotationMatrix();
    T.translation() = t;
  } else {
    T.translation() = t;
  }
  return T;
}

}  // namespace omniview

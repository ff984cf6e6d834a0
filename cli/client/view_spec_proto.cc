#include "cli/client/view_spec_proto.h"

#include <charconv>
#include <cmath>
#include <map>
#include <sstream>

#include "cli/args.h"
#include "core/view/view_yaml.h"

namespace omniview::cli {
namespace {

std::string trim_blanks(const std::string& s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

double parse_number(const std::string& text, const std::string& what) {
  const std::string t = trim_blanks(text);
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (t.empty() || end != t.c_str() + t.size() || !std::isfinite(v)) {
    throw UsageError(what + ": expected a number, got '" + text + "'");
  }
  return v;
}

int parse_integer(const std::string& text, const std::string& what) {
  const std::string t = trim_blanks(text);
  int v = 0;
  const auto [end, error] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (t.empty() || error != std::errc() || end != t.data() + t.size()) {
    throw UsageError(what + ": expected an integer, got '" + text + "'");
  }
  return v;
}

// "1, 2.5,3" -> exactly n numbers.
std::vector<double> parse_numbers(const std::string& text, size_t n, const std::string& what) {
  std::vector<double> values;
  std::stringstream parts(text);
  for (std::string part; std::getline(parts, part, ',');) values.push_back(parse_number(part, what));
  if (values.size() != n) {
    throw UsageError(what + ": expected " + std::to_string(n) + " comma-separated numbers, got '" + text + "'");
  }
  return values;
}

// Short names people type for the common keys.
std::string canonical_key(const std::string& key) {
  static const std::map<std::string, std::string> aliases{
      {"pan", "yaw_deg"},   {"yaw", "yaw_deg"},       {"tilt", "pitch_deg"},      {"pitch", "pitch_deg"},
      {"roll", "roll_deg"}, {"hfov", "hfov_deg"},     {"vfov", "vfov_deg"},       {"fov", "fov_deg"},
      {"xyz", "position"},  {"pose.xyz", "position"}, {"pose.ypr_deg", "ypr_deg"}};
  const auto it = aliases.find(key);
  return it == aliases.end() ? key : it->second;
}

// Clears the fields of `full` whose YAML key `node` does not give.
v1::ViewSpec only_given_fields(v1::ViewSpec full, const YAML::Node& node) {
  const YAML::Node pose = node["pose"];
  const bool has_xyz = pose && pose["xyz"], has_ypr = pose && pose["ypr_deg"];
  const auto* descriptor = full.GetDescriptor();
  const auto* reflection = full.GetReflection();
  for (int i = 0; i < descriptor->field_count(); ++i) {
    const auto* field = descriptor->field(i);
    const std::string& name = field->name();
    bool given = false;
    if (name == "type") {
      given = true;  // required by the schema
    } else if (name == "position") {
      given = has_xyz;
    } else if (name == "yaw_deg" || name == "pitch_deg" || name == "roll_deg") {
      given = has_ypr;
    } else {
      given = static_cast<bool>(node[name]);
    }
    if (!given) reflection->ClearField(&full, field);
  }
  return full;
}

}  // namespace

std::vector<v1::ViewSpec> views_from_yaml(const YamlReader& reader) {
  const std::vector<ViewSpec> parsed = parse_views(reader);  // checks keys, types, values
  const YAML::Node& root = reader.root();
  std::vector<YAML::Node> nodes;
  if (root["views"]) {
    for (const auto& node : root["views"]) nodes.push_back(node);
  } else {
    nodes.push_back(root);
  }
  std::vector<v1::ViewSpec> specs;
  for (size_t i = 0; i < parsed.size(); ++i) specs.push_back(only_given_fields(to_proto(parsed[i]), nodes[i]));
  return specs;
}

std::vector<v1::ViewSpec> load_view_file(const std::string& path) {
  return views_from_yaml(YamlReader::from_file(path));
}

void apply_setting(const std::string& assignment, v1::ViewSpec& spec) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) throw UsageError("--set '" + assignment + "': expected KEY=VALUE");
  const std::string key = canonical_key(trim_blanks(assignment.substr(0, eq)));
  const std::string value = trim_blanks(assignment.substr(eq + 1));
  const std::string what = "--set " + key;
  try {
    if (key == "type") return spec.set_type(to_proto(view_type_from_string(value, what)));
    if (key == "fusion") return spec.set_fusion(to_proto(fusion_from_string(value, what)));
    if (key == "depth") return spec.set_depth(to_proto(depth_from_string(value, what)));
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  if (key == "position") {
    const auto v = parse_numbers(value, 3, what);
    spec.mutable_position()->set_x(v[0]);
    spec.mutable_position()->set_y(v[1]);
    spec.mutable_position()->set_z(v[2]);
    return;
  }
  if (key == "ypr_deg") {
    const auto v = parse_numbers(value, 3, what);
    spec.set_yaw_deg(v[0]);
    spec.set_pitch_deg(v[1]);
    spec.set_roll_deg(v[2]);
    return;
  }
  // The remaining keys are the proto's scalar fields, named as in the YAML.
  const auto* field = spec.GetDescriptor()->FindFieldByName(key);
  using Type = google::protobuf::FieldDescriptor;
  const auto* reflection = spec.GetReflection();
  switch (field ? field->cpp_type() : Type::CPPTYPE_MESSAGE) {
    case Type::CPPTYPE_DOUBLE:
      return reflection->SetDouble(&spec, field, parse_number(value, what));
    case Type::CPPTYPE_INT32:
      return reflection->SetInt32(&spec, field, parse_integer(value, what));
    case Type::CPPTYPE_STRING:
      return reflection->SetString(&spec, field, value);
    case Type::CPPTYPE_BOOL:
      if (value == "true" || value == "on" || value == "yes" || value == "1") return reflection->SetBool(&spec, field, true);
      if (value == "false" || value == "off" || value == "no" || value == "0") return reflection->SetBool(&spec, field, false);
      throw UsageError(what + ": expected true or false, got '" + value + "'");
    default:
      throw UsageError("--set: unknown key '" + key + "' (see 'omniview views --help')");
  }
}

const char* settable_keys_help() {
  return R"(--set keys (the view YAML keys; angles in degrees, distances in metres):
  name, type (perspective|birdseye|cylindrical|mercator|equirectangular|fisheye), source,
  width, height, frame, position=X,Y,Z, ypr_deg=YAW,PITCH,ROLL, yaw_deg (pan), pitch_deg
  (tilt, positive looks down), roll_deg (roll), hfov_deg (hfov), distance, height_m,
  ground_z, ground (true|false: the surface ends at the ground plane z = ground_z),
  radius, vfov_deg (vfov), azimuth_span_deg, lat_min_deg, lat_max_deg,
  fov_deg (fov), fusion (blend, the default|nearest), feather_px, gain_compensation
  (true, the default|false: even out the cameras' exposures in a blend), overlay (true|false: draw the robot
  into a perspective or birdseye view), overlay_opacity (0..1), depth (fixed, the
  default|measured: the surface follows what the source measures: its lidar clouds, Spot's
  depth images)
)";
}

}  // namespace omniview::cli

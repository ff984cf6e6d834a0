#include "core/view/view_yaml.h"

#include <algorithm>
#include <iomanip>
#include <sstream>

#include "core/view/view_keys.h"

namespace omniview {
namespace {

// validate() names the field it rejects ("view 'v': fov_deg must be ..."). Returns the YAML
// key that field comes from when `n` gives it, so the error can point at that key's line;
// empty when the message names no such key.
std::string key_rejected_by_validate(const std::string& message, const ViewSpec& s, const YAML::Node& n) {
  const std::string prefix = "view '" + s.name + "': ";
  if (message.rfind(prefix, 0) != 0) return "";
  const size_t end = message.find(' ', prefix.size());
  const std::string label = message.substr(prefix.size(), end - prefix.size());
  // "lat_min_deg/lat_max_deg" names a pair; a bird's-eye view's height_m is labelled
  // "height", checked after the pixel height (so that one is fine when height_m is not).
  std::vector<std::string> keys;
  for (size_t from = 0, slash; from <= label.size(); from = slash + 1) {
    slash = std::min(label.find('/', from), label.size());
    keys.push_back(label.substr(from, slash - from));
  }
  if (label == "height" && s.type == ViewType::kBirdseye && s.height >= 1 && s.height <= kMaxViewSide) {
    keys = {"height_m"};
  }
  for (const auto& k : keys) {
    if (n.IsMap() && n[k]) return k;
  }
  return "";
}

// Views are told apart by name (the CLI writes NAME.png, the daemon addresses them by it).
void reject_repeated_names(const YamlReader& r, const YAML::Node& list, const std::vector<ViewSpec>& views) {
  for (size_t i = 0; i < views.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      if (views[i].name != views[j].name) continue;
      const std::string at = "views[" + std::to_string(i) + "]";
      const std::string unnamed = list[i]["name"] ? "" : " (a view without 'name' is called 'view')";
      r.fail(list[i]["name"] ? list[i]["name"] : list[i], at + ".name",
             "view name '" + views[i].name + "' is already used by views[" + std::to_string(j) + "] on line " +
                 std::to_string(list[j].Mark().line + 1) + unnamed + "; names must be unique");
    }
  }
}

}  // namespace

ViewSpec parse_view(const YamlReader& r, const YAML::Node& n, const std::string& path) {
  r.expect_keys(n, path, {"name", "type", "width", "height", "frame", "pose", "hfov_deg", "distance", "height_m",
                          "ground_z", "radius", "vfov_deg", "azimuth_span_deg", "lat_min_deg", "lat_max_deg",
                          "fov_deg", "fusion", "feather_px", "gain_compensation", "source", "overlay",
                          "overlay_opacity", "ground", "depth"});
  const auto key = [&](const char* k) { return path.empty() ? std::string(k) : path + "." + k; };
  ViewSpec s = default_view_spec([&] {
    const YAML::Node t = r.required(n, "type", path);
    try {
      return view_type_from_string(r.text(t, key("type")), "");
    } catch (const std::invalid_argument& e) {
      r.fail(t, key("type"), e.what());
    }
  }());
  if (n["name"]) s.name = r.text(n["name"], key("name"));
  if (n["width"]) s.width = r.integer(n["width"], key("width"));
  if (n["height"]) s.height = r.integer(n["height"], key("height"));
  if (n["frame"]) s.frame = r.text(n["frame"], key("frame"));
  if (n["source"]) s.source = r.text(n["source"], key("source"));
  if (const YAML::Node pose = n["pose"]) {
    r.expect_keys(pose, key("pose"), {"xyz", "ypr_deg"});
    if (pose["xyz"]) {
      const auto v = r.numbers(pose["xyz"], key("pose.xyz"), 3);
      s.position = Vec3(v[0], v[1], v[2]);
    }
    if (pose["ypr_deg"]) {
      const auto a = r.numbers(pose["ypr_deg"], key("pose.ypr_deg"), 3);
      s.yaw_deg = a[0], s.pitch_deg = a[1], s.roll_deg = a[2];
    }
  }
  // A key of another type would be ignored: say so rather than render something else.
  for (const auto& k : surface_keys()) {
    if (const auto why = inapplicable_key(k, s.type); n[k] && !why.empty()) r.fail(n[k], key(k.c_str()), why);
  }
  const std::pair<const char*, double*> numbers[] = {
      {"hfov_deg", &s.hfov_deg},         {"distance", &s.distance},       {"height_m", &s.height_m},
      {"ground_z", &s.ground_z},         {"radius", &s.radius},           {"vfov_deg", &s.vfov_deg},
      {"azimuth_span_deg", &s.azimuth_span_deg}, {"lat_min_deg", &s.lat_min_deg}, {"lat_max_deg", &s.lat_max_deg},
      {"fov_deg", &s.fov_deg},           {"feather_px", &s.feather_px},   {"overlay_opacity", &s.overlay_opacity}};
  for (const auto& [k, field] : numbers) {
    if (n[k]) *field = r.number(n[k], key(k));
  }
  if (n["overlay"]) s.overlay = r.boolean(n["overlay"], key("overlay"));
  if (n["ground"]) s.ground = r.boolean(n["ground"], key("ground"));
  if (n["gain_compensation"]) s.gain_compensation = r.boolean(n["gain_compensation"], key("gain_compensation"));
  if (n["fusion"]) {
    try {
      s.fusion = fusion_from_string(r.text(n["fusion"], key("fusion")), "");
    } catch (const std::invalid_argument& e) {
      r.fail(n["fusion"], key("fusion"), e.what());
    }
  }
  if (n["depth"]) {
    try {
      s.depth = depth_from_string(r.text(n["depth"], key("depth")), "");
    } catch (const std::invalid_argument& e) {
      r.fail(n["depth"], key("depth"), e.what());
    }
  }
  try {
    validate(s);
  } catch (const std::invalid_argument& e) {
    const std::string rejected = key_rejected_by_validate(e.what(), s, n);
    if (!rejected.empty()) r.fail(n[rejected], key(rejected.c_str()), e.what());
    r.fail(n, path, e.what());
  }
  return s;
}

std::vector<ViewSpec> load_views(const std::string& file) { return parse_views(YamlReader::from_file(file)); }

std::vector<ViewSpec> parse_views(const YamlReader& r) {
  const YAML::Node& root = r.root();
  if (!root.IsMap()) r.fail(root, "", "expected a view (a map with 'type') or 'views: [...]'");
  std::vector<ViewSpec> views;
  if (root["views"]) {
    r.expect_keys(root, "", {"views"});
    const YAML::Node list = root["views"];
    if (!list.IsSequence() || list.size() == 0) r.fail(list, "views", "expected a non-empty list of views");
    for (size_t i = 0; i < list.size(); ++i) views.push_back(parse_view(r, list[i], "views[" + std::to_string(i) + "]"));
    reject_repeated_names(r, list, views);
  } else {
    views.push_back(parse_view(r, root, ""));
  }
  return views;
}

namespace {

// 12 significant digits: 0.42 and 0.9 print as written, not as 0.41999999999999998 (yaml-cpp
// turns a double into text when it is assigned, with every digit a double can hold).
YAML::Node number(double v) {
  std::ostringstream text;
  text << std::setprecision(12) << v;
  return YAML::Node(text.str());
}

YAML::Node numbers(std::initializer_list<double> values) {
  YAML::Node n(YAML::NodeType::Sequence);
  for (double v : values) n.push_back(number(v));
  return n;
}

}  // namespace

YAML::Node view_to_yaml(const ViewSpec& s) {
  YAML::Node n;
  n["name"] = s.name;
  n["type"] = to_string(s.type);
  n["width"] = s.width;
  n["height"] = s.height;
  if (!s.source.empty()) n["source"] = s.source;
  if (!s.frame.empty()) n["frame"] = s.frame;
  n["pose"]["xyz"] = numbers({s.position.x(), s.position.y(), s.position.z()});
  n["pose"]["ypr_deg"] = numbers({s.yaw_deg, s.pitch_deg, s.roll_deg});
  switch (s.type) {
    case ViewType::kPerspective:
      n["hfov_deg"] = number(s.hfov_deg);
      n["distance"] = number(s.distance);
      break;
    case ViewType::kBirdseye:
      n["hfov_deg"] = number(s.hfov_deg);
      n["height_m"] = number(s.height_m);
      n["ground_z"] = number(s.ground_z);
      break;
    case ViewType::kCylindrical:
      n["radius"] = number(s.radius);
      n["vfov_deg"] = number(s.vfov_deg);
      n["azimuth_span_deg"] = number(s.azimuth_span_deg);
      break;
    case ViewType::kMercator:
    case ViewType::kEquirectangular:
      n["radius"] = number(s.radius);
      n["azimuth_span_deg"] = number(s.azimuth_span_deg);
      n["lat_min_deg"] = number(s.lat_min_deg);
      n["lat_max_deg"] = number(s.lat_max_deg);
      break;
    case ViewType::kFisheye:
      n["radius"] = number(s.radius);
      n["fov_deg"] = number(s.fov_deg);
      break;
  }
  if (s.ground) {
    n["ground"] = true;
    n["ground_z"] = number(s.ground_z);
  }
  // Only when measured: files written for fixed views stay as every earlier version wrote them.
  if (s.depth == Depth::kMeasured) n["depth"] = to_string(s.depth);
  n["fusion"] = to_string(s.fusion);
  n["feather_px"] = number(s.feather_px);
  n["gain_compensation"] = s.gain_compensation;
  if (s.type == ViewType::kPerspective || s.type == ViewType::kBirdseye) {
    n["overlay"] = s.overlay;
    n["overlay_opacity"] = number(s.overlay_opacity);
  }
  return n;
}

}  // namespace omniview

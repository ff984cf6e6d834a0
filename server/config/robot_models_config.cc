// `robot_models`: which robot the daemon draws into the views of which source.
#include <map>
#include <set>

#include "server/config/config_parts.h"

namespace omniview::config_parts {

std::vector<RobotModelEntry> parse_robot_models(const YamlReader& r, const YAML::Node& n,
                                                const std::vector<SourceEntry>& sources, const std::string& folder) {
  std::vector<RobotModelEntry> models;
  if (!n.IsDefined() || n.IsNull()) return models;
  if (!n.IsSequence()) r.fail(n, "robot_models", "expected a list of {source, urdf, ...}");
  std::set<std::string> source_names;
  for (const auto& s : sources) source_names.insert(s.name);
  std::map<std::string, std::string> seen;  // source -> path of its entry
  for (size_t i = 0; i < n.size(); ++i) {
    RobotModelEntry m;
    m.path = "robot_models[" + std::to_string(i) + "]";
    m.node = n[i];
    r.expect_keys(m.node, m.path, {"source", "urdf", "mesh_path", "frame", "joints", "outline_px"});
    const YAML::Node source = r.required(m.node, "source", m.path);
    m.source = r.text(source, m.path + ".source");
    if (!source_names.count(m.source)) r.fail(source, m.path + ".source", "there is no source named '" + m.source + "'");
    if (const auto [it, fresh] = seen.emplace(m.source, m.path); !fresh) {
      r.fail(source, m.path + ".source", "source '" + m.source + "' already has a robot model (" + it->second + ")");
    }
    m.urdf_file = resolve_config_path(folder, r.text(r.required(m.node, "urdf", m.path), m.path + ".urdf"));
    if (const YAML::Node paths = m.node["mesh_path"]) {
      if (!paths.IsSequence()) r.fail(paths, m.path + ".mesh_path", "expected a list of folders");
      for (size_t k = 0; k < paths.size(); ++k) {
        m.mesh_path.push_back(resolve_config_path(folder, r.text(paths[k], m.path + ".mesh_path")));
      }
    }
    if (m.node["frame"]) m.frame = r.text(m.node["frame"], m.path + ".frame");
    if (const YAML::Node joints = m.node["joints"]) {
      if (!joints.IsMap()) r.fail(joints, m.path + ".joints", "expected a map {joint: position}");
      for (const auto& kv : joints) {
        m.joints[kv.first.Scalar()] = r.number(kv.second, m.path + ".joints." + kv.first.Scalar());
      }
    }
    if (const YAML::Node outline = m.node["outline_px"]) {
      m.outline_px = r.integer(outline, m.path + ".outline_px");
      if (m.outline_px < 0 || m.outline_px > 8) r.fail(outline, m.path + ".outline_px", "must be in 0..8");
    }
    models.push_back(std::move(m));
  }
  return models;
}

}  // namespace omniview::config_parts

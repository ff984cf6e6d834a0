// `sources:` and `views:`. Sources are only recorded here (name, type, their YAML): the
// daemon builds them through the source registry, whose factories read the type's own keys.
#include <algorithm>
#include <filesystem>
#include <map>

#include "core/view/view_yaml.h"
#include "server/config/config_parts.h"

namespace omniview::config_parts {

std::vector<SourceEntry> parse_sources(const YamlReader& r, const YAML::Node& n) {
  if (!n.IsDefined() || n.IsNull()) r.fail(r.root(), "", "missing required key 'sources' (at least one source)");
  if (!n.IsSequence() || n.size() == 0) r.fail(n, "sources", "expected a list of at least one {name, type, ...}");
  std::vector<SourceEntry> sources;
  std::map<std::string, std::string> seen;  // name -> path of its first entry
  for (size_t i = 0; i < n.size(); ++i) {
    SourceEntry source;
    source.path = "sources[" + std::to_string(i) + "]";
    source.node = n[i];
    if (!source.node.IsMap()) r.fail(source.node, source.path, "expected a map with name, type and the type's keys");
    const YAML::Node name = r.required(source.node, "name", source.path);
    source.name = r.text(name, source.path + ".name");
    if (source.name.empty()) r.fail(name, source.path + ".name", "is empty");
    source.type = r.text(r.required(source.node, "type", source.path), source.path + ".type");
    const auto [it, inserted] = seen.emplace(source.name, source.path);
    if (!inserted) r.fail(name, source.path + ".name", "'" + source.name + "' is already the name of " + it->second);
    sources.push_back(std::move(source));
  }
  return sources;
}

std::vector<ViewSpec> parse_daemon_views(const YamlReader& r, const YAML::Node& n,
                                         const std::vector<SourceEntry>& sources, const Limits& limits) {
  std::vector<ViewSpec> views;
  if (!n.IsDefined() || n.IsNull()) return views;
  if (!n.IsSequence()) r.fail(n, "views", "expected a list of views");
  if (n.size() > static_cast<size_t>(limits.max_views)) {
    r.fail(n[limits.max_views], "views",
           std::to_string(n.size()) + " views, more than limits.max_views (" + std::to_string(limits.max_views) + ")");
  }
  std::map<std::string, std::string> seen;  // name -> path of its first entry
  for (size_t i = 0; i < n.size(); ++i) {
    const std::string path = "views[" + std::to_string(i) + "]";
    ViewSpec view = parse_view(r, n[i], path);
    if (view.source.empty()) {
      view.source = sources.front().name;
    } else {
      bool known = false;
      std::string names;
      for (const auto& s : sources) {
        known = known || s.name == view.source;
        names += (names.empty() ? "" : ", ") + s.name;
      }
      if (!known) {
        r.fail(n[i]["source"], path + ".source", "no source is named '" + view.source + "' (sources: " + names + ")");
      }
    }
    const int64_t pixels = int64_t{view.width} * view.height;
    if (pixels > limits.max_view_pixels) {
      r.fail(n[i], path, "view '" + view.name + "' is " + std::to_string(view.width) + "x" +
                             std::to_string(view.height) + " = " + std::to_string(pixels) +
                             " pixels, more than limits.max_view_pixels (" + std::to_string(limits.max_view_pixels) +
                             ")");
    }
    const YAML::Node name = n[i]["name"] ? n[i]["name"] : n[i];
    const auto [it, inserted] = seen.emplace(view.name, path);
    if (!inserted) r.fail(name, path + ".name", "'" + view.name + "' is already the name of " + it->second);
    views.push_back(std::move(view));
  }
  return views;
}

void apply_views_file(const YamlReader& config_reader, const YAML::Node& node, const std::string& file,
                      const std::vector<SourceEntry>& sources, const Limits& limits, std::vector<ViewSpec>& views) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) return;  // nothing saved yet
  if (std::filesystem::is_directory(file, ec)) config_reader.fail(node, "views_file", "'" + file + "' is a folder");
  const YamlReader r = YamlReader::from_file(file);
  const YAML::Node& root = r.root();
  if (root.IsNull()) return;  // an empty file: no views
  if (!root.IsMap()) r.fail(root, "", "expected a map with 'views:' (as 'omniview views save' writes it)");
  r.expect_keys(root, "", {"views"});
  for (ViewSpec& saved : parse_daemon_views(r, root["views"], sources, limits)) {
    const auto same = std::find_if(views.begin(), views.end(), [&](const ViewSpec& v) { return v.name == saved.name; });
    if (same != views.end()) {
      *same = std::move(saved);
    } else {
      views.push_back(std::move(saved));
    }
  }
  if (views.size() > static_cast<size_t>(limits.max_views)) {
    config_reader.fail(node, "views_file",
                       "'views' and '" + file + "' together hold " + std::to_string(views.size()) +
                           " views, more than limits.max_views (" + std::to_string(limits.max_views) + ")");
  }
}

}  // namespace omniview::config_parts

// View definitions in YAML: the schema the CLI's --view files and the daemon's config
// share. One view per file, or a list under `views:`. Keys (all but `type` optional):
//   name, type, source, width, height, frame, pose: {xyz: [x, y, z], ypr_deg: [yaw, pitch, roll]},
//   hfov_deg, distance, height_m, ground_z, radius, vfov_deg, azimuth_span_deg,
//   lat_min_deg, lat_max_deg, fov_deg, fusion (nearest | blend), feather_px,
//   gain_compensation (true | false; blend views: even out the cameras' exposures),
//   ground (true | false; every type but birdseye: the surface ends at the ground plane z =
//   ground_z, see view.h), overlay, overlay_opacity
#pragma once

#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "core/io/yaml_reader.h"
#include "core/view/view_spec.h"

namespace omniview {

// Reads one view map at `path` (for messages) and validates it.
ViewSpec parse_view(const YamlReader& reader, const YAML::Node& node, const std::string& path);

// A file holding one view, or `views: [...]`. Throws ConfigError naming file, line, key.
std::vector<ViewSpec> load_views(const std::string& file);
std::vector<ViewSpec> parse_views(const YamlReader& reader);

// The YAML that parse_view() reads back to `spec` (round-trips).
YAML::Node view_to_yaml(const ViewSpec& spec);

}  // namespace omniview

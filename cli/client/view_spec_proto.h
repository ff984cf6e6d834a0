// View definitions between the forms a user gives them (view YAML files, --set key=value)
// and the API's ViewSpec, whose fields are all optional: set means "this changes".
#pragma once

#include <string>
#include <vector>

#include "core/io/yaml_reader.h"
#include "core/view/view_spec.h"
#include "omniview/v1/omniview.pb.h"

namespace omniview::cli {

v1::ViewType to_proto(ViewType type);
ViewType from_proto(v1::ViewType type);  // throws std::invalid_argument for UNSPECIFIED
v1::Fusion to_proto(Fusion fusion);

// Every field set.
v1::ViewSpec to_proto(const ViewSpec& spec);
// Unset fields take the defaults of the spec's type (perspective when unset).
ViewSpec from_proto(const v1::ViewSpec& spec);

// Each view of a view YAML file (one view, or `views: [...]`), checked by core's parser,
// with only the fields the file gives set (type always; name only when the file has one).
// Throws ConfigError naming file, line and key.
std::vector<v1::ViewSpec> views_from_yaml(const YamlReader& reader);
std::vector<v1::ViewSpec> load_view_file(const std::string& path);

// Applies one `--set key=value`. Keys are the YAML keys (hfov_deg, width, fusion, ...) plus
// position=x,y,z, ypr_deg=yaw,pitch,roll and the aliases pan, tilt, roll, yaw, pitch, hfov,
// vfov, fov. Throws UsageError naming the key for an unknown key or a bad value.
void apply_setting(const std::string& assignment, v1::ViewSpec& spec);
// The keys, for --help.
const char* settable_keys_help();

// Zoom as a photographer says it: zoom 1 is a 90 deg horizontal field of view and zoom X
// has X times its focal length: hfov = 2 atan(tan(45 deg) / X).
double hfov_from_zoom(double zoom);
double zoom_from_hfov(double hfov_deg);

}  // namespace omniview::cli

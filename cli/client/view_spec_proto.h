// View definitions between the forms a user gives them (view YAML files, --set key=value)
// and the API's ViewSpec, whose fields are all optional: set means "this changes". The
// conversions between core's ViewSpec and the proto are the daemon's own
// (server/convert/convert.h), so both ends read the API the same way.
#pragma once

#include <string>
#include <vector>

#include "core/io/yaml_reader.h"
#include "core/view/view_spec.h"
#include "omniview/v1/omniview.pb.h"
#include "server/convert/convert.h"

namespace omniview::cli {

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

}  // namespace omniview::cli

// Which surface keys (YAML keys and API field names) each view type uses, so that a key
// given for the wrong type is an error rather than silently ignored.
#pragma once

#include <string>
#include <vector>

#include "core/view/view_spec.h"

namespace omniview {

// Every type-specific key: hfov_deg, distance, height_m, ground_z, radius, vfov_deg,
// azimuth_span_deg, lat_min_deg, lat_max_deg, fov_deg.
const std::vector<std::string>& surface_keys();
// Those a view of `type` uses.
const std::vector<std::string>& surface_keys(ViewType type);
// "" when `key` applies to `type` (or is no surface key at all), else a message naming the
// key, the type and the keys it has: "fov_deg does not apply to perspective views (their
// keys: hfov_deg, distance)".
std::string inapplicable_key(const std::string& key, ViewType type);

}  // namespace omniview

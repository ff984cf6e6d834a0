// Small readers shared by the file-based sources.
#pragma once

#include <memory>
#include <string>

#include "core/rig/rig.h"
#include "server/source/source_registry.h"

namespace omniview {

// `key` of the source's map as a path, resolved against the config's folder.
std::string config_path(const SourceConfig& config, const char* key);

// A positive, finite number at `key`, or `fallback` when the key is absent.
double positive_number(const SourceConfig& config, const char* key, double fallback);

// The rig at `rig` (our YAML or a camchain, with rig_frame / rig_pose for the latter).
std::shared_ptr<const Rig> load_config_rig(const SourceConfig& config);

}  // namespace omniview

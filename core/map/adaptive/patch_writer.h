// Writes interpolated patches straight into the map: coordinates and encoding fused, eight
// pixels at a time, so an interpolated pixel costs a few vector instructions and one store.
#pragma once

#include <vector>

#include "core/map/adaptive/block_plan.h"

namespace omniview::map_internal {

void write_patches(const std::vector<Patch>& patches, const std::vector<CameraSetup>& setups, FusionMap& map);

}  // namespace omniview::map_internal

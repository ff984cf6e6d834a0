// Which output pixels of a blend map gain estimation reads: a regular subsample of the
// pixels where two cameras overlap, chosen once when the map is built.
#pragma once

#include <cstdint>
#include <vector>

#include "core/map/fusion_map.h"

namespace omniview {

// A few thousand samples pin a mean intensity to well under a grey level while costing
// microseconds per frame.
inline constexpr size_t kMaxGainSamples = 8192;

// Indices (row-major) of up to `max_samples` pixels of `map` that have a secondary camera,
// spread evenly over the overlap. Empty for maps without blending.
std::vector<uint32_t> choose_overlap_samples(const FusionMap& map, size_t max_samples = kMaxGainSamples);

}  // namespace omniview

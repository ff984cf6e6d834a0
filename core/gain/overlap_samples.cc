#include "core/gain/overlap_samples.h"

namespace omniview {

std::vector<uint32_t> choose_overlap_samples(const FusionMap& map, size_t max_samples) {
  std::vector<uint32_t> samples;
  if (map.secondary.empty() || max_samples == 0) return samples;
  // Every pixel both cameras see inside their usable regions, blended or not: where
  // parallax narrows the blend (fusion_map.cc) the cameras still show the same surface, and
  // their whole common area measures the exposures better than the band alone.
  const auto overlapping = [&](size_t i) {
    return map.primary[i].cam != kNoCamera && map.secondary[i].cam != kNoCamera;
  };
  size_t count = 0;
  for (size_t i = 0; i < map.primary.size(); ++i) count += overlapping(i);
  if (count == 0) return samples;
  // Every stride-th overlapping pixel, in a fixed order: the same map gives the same samples.
  const size_t stride = (count + max_samples - 1) / max_samples;
  samples.reserve(count / stride + 1);
  size_t seen = 0;
  for (size_t i = 0; i < map.primary.size(); ++i) {
    if (!overlapping(i)) continue;
    if (seen++ % stride == 0) samples.push_back(static_cast<uint32_t>(i));
  }
  return samples;
}

}  // namespace omniview

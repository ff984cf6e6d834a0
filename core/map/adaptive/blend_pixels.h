// The blend policy's entries at chosen pixels of one output row, as the per-pixel builder
// makes them (blend_kernels.h). The adaptive builder of a blend map interpolates only
// where a single camera sees every sample of a block (there the map is that camera's
// coordinates at full weight, as for nearest-centre); the pixels of every other block (two
// cameras' overlap, where the seam's band and gain compensation's samples lie) come from
// here.
#pragma once

#include <cstdint>
#include <vector>

#include "core/map/fusion_map.h"
#include "core/map/map_kernels.h"

namespace omniview::map_internal {

class BlendPixels {
 public:
  BlendPixels(const View& view, const std::vector<CameraSetup>& setups, const Occlusion* occlusion = nullptr)
      : view_(view), setups_(setups), occlusion_(occlusion) {}

  // Writes the primary, secondary and primary weight of pixels (columns[i], row), i < n,
  // into `map`, and sets used[c] for every camera c they read.
  void write(int row, const int* columns, int n, FusionMap& map, std::vector<uint8_t>& used);

 private:
  const View& view_;
  const std::vector<CameraSetup>& setups_;
  const Occlusion* occlusion_;
  RowScratch scratch_{0};
  std::vector<float> qx_, qy_, qz_, best_, second_;
  std::vector<uint8_t> q_valid_, judged_;
  std::vector<int> neighbours_, blend_index_;
  std::vector<MapEntry> primary_, secondary_;
};

}  // namespace omniview::map_internal

// The exact nearest-centre winner (camera and its source coordinates) at chosen pixels of
// one output row: what the per-pixel builder computes, for the adaptive builder's lattice
// points and for the pixels it cannot interpolate.
#pragma once

#include <cstdint>
#include <vector>

#include "core/map/map_kernels.h"

namespace omniview::map_internal {

// Winners at a set of pixels, structure of arrays (the selection loops vectorise). May
// hold more entries than pixels were sampled (padding, see winners.cc).
struct Winners {
  std::vector<float> u, v;
  std::vector<uint32_t> cam;        // kNoCamera where no camera sees the pixel
  std::vector<uint8_t> on_surface;  // the view's surface exists there (not a fisheye corner)
};

class WinnerSampler {
 public:
  WinnerSampler(const View& view, const std::vector<CameraSetup>& setups) : view_(view), setups_(setups) {}

  // Winners at pixels (columns[i], row), i < n, into out[i] (out grows to hold them).
  void sample(int row, const int* columns, int n, Winners& out);

 private:
  const View& view_;
  const std::vector<CameraSetup>& setups_;
  RowScratch scratch_{0};
  std::vector<float> best_;
  std::vector<int> columns_;  // padded
};

}  // namespace omniview::map_internal

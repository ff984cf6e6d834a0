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
  // On measured depth or with occlusion only: the surface point (view frame), whether it
  // is judged (Occlusion::judged), and whether a camera that would have won was dropped as
  // hidden there (the adaptive builder must not interpolate across such a sample: between
  // two samples that camera may see the surface again).
  std::vector<float> x, y, z;
  std::vector<uint8_t> judged, better_hidden;
  // Blend only: whether two or more cameras see the pixel (the blend map is then not the
  // winner's coordinates alone: a second camera and a weight).
  std::vector<uint8_t> shared;
};

class WinnerSampler {
 public:
  // `occlusion` (optional): cameras that see a pixel's surface point hidden do not compete.
  // `blend`: for a blend map: Winners::shared is set, and where a single camera sees a
  // pixel, it wins only where its feather weight is above 0 (as in the blend rule).
  WinnerSampler(const View& view, const std::vector<CameraSetup>& setups, const Occlusion* occlusion = nullptr,
                bool blend = false)
      : view_(view), setups_(setups), occlusion_(occlusion), keep_points_(occlusion || view.measured()), blend_(blend) {}

  // Winners at pixels (columns[i], row), i < n, into out[i] (out grows to hold them).
  void sample(int row, const int* columns, int n, Winners& out);

 private:
  const View& view_;
  const std::vector<CameraSetup>& setups_;
  const Occlusion* occlusion_;
  const bool keep_points_;
  const bool blend_;
  RowScratch scratch_{0};
  std::vector<float> best_, best_unoccluded_;
  std::vector<int> columns_;  // padded
  std::vector<uint8_t> seen_by_;  // blend: how many cameras see each pixel (a rig has at most 254)
};

}  // namespace omniview::map_internal

// Occlusion for the map builder: per camera, the depth of the nearest surface in front of
// each cell of its image, so that a surface point a nearer surface hides from a camera is
// not taken from that camera (DESIGN.md, "Unseen is black"). Views on measured depth get it
// from the same depth buffers the cloud colourer uses (core/depth/camera_occluders.h);
// views on fixed surfaces have none, and their maps are what they always were.
#pragma once

#include <cstddef>
#include <vector>

namespace omniview {

// One camera's covering depth per cell (cloud_internal::CameraPass::occluder's layout):
// cell (row, col) of pixel (u, v) is (int(v * inv_cell + offset), int(u * inv_cell + offset)).
struct CameraOccluder {
  std::vector<float> depth;  // rows x cols, range from the camera's centre (m); +max: nothing
  int rows = 0, cols = 0;
  float inv_cell = 1, offset = 0;
  bool empty() const { return depth.empty(); }
  // (u, v) inside the camera's image [0, W-1] x [0, H-1].
  float at(float u, float v) const {
    return depth[size_t(static_cast<int>(v * inv_cell + offset)) * size_t(cols) + static_cast<int>(u * inv_cell + offset)];
  }
};

// The rule, shared with the cloud colourer (ColourOptions::occlusion_tolerance_*): a point is
// hidden when farther than the covering surface by more than rel * range + abs, so that a
// surface seen at a grazing angle does not hide itself.
inline bool hidden_behind(float range, float covering, float tolerance_rel, float tolerance_m) {
  return range > covering * (1.f + tolerance_rel) + tolerance_m;
}

struct Occlusion {
  std::vector<CameraOccluder> cameras;  // one per rig camera (empty: that camera hides nothing)
  float tolerance_rel = 0.1f, tolerance_m = 0.1f;
  // The view pixels (row-major) the test applies to, 0 to leave a pixel out; empty: all.
  // A measured-depth view leaves out the band where measured depth fades into the fixed
  // surface: a point there is a mix of two guesses, often behind the measured surface the
  // cameras see (it would come out black where the world is plainly in sight).
  std::vector<uint8_t> judged;
};

}  // namespace omniview

// Occlusion for the map builder: per camera, the depth of the nearest surface in front of
// each cell of its image, so that a surface point a nearer surface hides from a camera is
// not taken from that camera (DESIGN.md, "Unseen is black"). Views on measured depth get it
// from core/depth/camera_occluders.h (the cloud colourer's buffer layout, projection and
// tolerance); views on fixed surfaces have none, and their maps are what they always were.
#pragma once

#include <cstddef>
#include <vector>

namespace omniview {

// One camera's covering depth per cell, cell (row, col) of pixel (u, v) being
// (int(v * inv_cell + offset), int(u * inv_cell + offset)) as in the colourer's depth buffer
// (cloud_internal::CameraPass). Stored in tiles of 4 x 4 cells, one cache line each: a view
// row often runs down a camera's columns (Spot's cameras are mounted rolled), and a
// row-major buffer then missed the cache at every pixel (the map build took 2.8x as long).
struct CameraOccluder {
  static constexpr int kTile = 4;
  std::vector<float> depth;  // tiled (see index()); range from the camera's centre (m), +max: nothing
  int rows = 0, cols = 0;    // cells
  int tile_cols = 0;         // tiles per row of tiles
  float inv_cell = 1, offset = 0;
  bool empty() const { return depth.empty(); }
  size_t index(int row, int col) const {
    return (size_t(row / kTile) * size_t(tile_cols) + size_t(col / kTile)) * (kTile * kTile) +
           size_t(row % kTile) * kTile + size_t(col % kTile);
  }
  // Fills the tiles from a row-major rows x cols buffer.
  void assign_row_major(const std::vector<float>& cells, int rows_, int cols_);
  // (u, v) inside the camera's image [0, W-1] x [0, H-1].
  float at(float u, float v) const {
    return depth[index(static_cast<int>(v * inv_cell + offset), static_cast<int>(u * inv_cell + offset))];
  }
};

inline void CameraOccluder::assign_row_major(const std::vector<float>& cells, int rows_, int cols_) {
  rows = rows_;
  cols = cols_;
  tile_cols = (cols + kTile - 1) / kTile;
  const int tile_rows = (rows + kTile - 1) / kTile;
  depth.assign(size_t(tile_rows) * size_t(tile_cols) * kTile * kTile, 0.f);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) depth[index(r, c)] = cells[size_t(r) * size_t(cols) + c];
  }
}

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

// Joins the tops of objects across the ground cells a lidar's rings skipped. A VLP-16's
// rings meet a box's top along arcs ~2 deg apart as the sensor sees them: on a crate 0.3 m
// below the sensor, 1.5 m away, two rings 0.36 m apart and nothing between. The view's gap
// fill leaves that alone (from the lidar the top is seen at 80 deg incidence, so the two
// rings are farther apart than a tenth of their range: a step), the top fell back to the
// ground there, and a bird's-eye view painted the crate's top at the floor's place (the
// golden bird's-eye view's largest error, half of it on one crate). Here the two tops are
// joined over the ground: an empty cell (no point at all in it, not even the floor: the
// rings' floor points rule out anything standing there) between two object tops at the
// same height, within a short reach, gets a point of the top between them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace omniview {

struct FlatTopOptions {
  float cell_m = 0.05f;  // ColumnOptions::cell_m: the same ground cells
  // Two tops farther apart than this are not joined: 2.5 rings on a top 0.3 m below a
  // VLP-16 at 1.5 m, while two separate objects that close rarely share a height.
  float max_gap_m = 0.5f;
  // Tops differing by more than this are not one surface (a ring under the top edge lies
  // a few cm below it: the golden room's low crate 2.3 cm).
  float max_step_m = 0.08f;
  // Tops farther than this from `centre` (the sensor) are not joined: it bounds the grid,
  // and far out the rings are too sparse to tell a top from two objects.
  float max_range_m = 25.f;
};

// A ground cell's top: the highest point of the cell's points above the ground, where
// nothing was measured above it (the sensor's rays passed over).
struct CellTop {
  int32_t ix = 0, iy = 0;  // floor(x / cell_m), floor(y / cell_m)
  float z = 0;
};

// The points that join `tops` across empty cells: along the grid's rows, columns and
// diagonals, an empty cell between two tops within max_gap_m and max_step_m gets a point at
// its centre, its height interpolated between them. `points` (a level frame, z up) say
// which cells are empty: any usable point in a cell, the floor's included, fills it; a
// walk from a top ends at the first cell that is not empty, and joins only when that cell
// is a top too.
std::vector<Eigen::Vector3f> flat_top_points(const std::vector<Eigen::Vector3f>& points,
                                             const std::vector<CellTop>& tops, const Eigen::Vector2f& centre,
                                             const FlatTopOptions& options = {});

}  // namespace omniview

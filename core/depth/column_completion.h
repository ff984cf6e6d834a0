// Completes measured geometry where a sensor's field cut an object short: things stand on
// the ground and their sides are mostly vertical (walls, pillars, boxes, people, trees: the
// "stixel world" of driver-assistance vision). A VLP-16's 16 rings span only -15..+15 deg,
// so a pillar 1.3 m away is measured between 0.45 and 1.15 m above the floor; a view that
// looks at its foot or above its top ring fell back to its fixed surface right beside the
// measured part (a ground plane behind the pillar's foot, a 3 m sphere in front of a wall
// 5 m away), and its cameras disagreed there. Each ground cell holding points above the
// ground gets a column of added points: down from its lowest point to the ground, and up
// past its highest where that point lay on the top of its sensor's field (the object may
// go on above; how far is unknown, so a limited height).
//
// The added points are geometry like the measured ones (a view's splat and the cameras'
// occluders take them alike): what a column gets wrong is what a table or an overhang is
// (the column fills the space below it down to the floor).
#pragma once

#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/depth/flat_tops.h"
#include "core/depth/free_space.h"
#include "core/rig/rig.h"

namespace omniview {

struct ColumnOptions {
  // Ground cells: 5 cm, a lidar's spacing along a ring at 3-10 m; a column stands at the
  // mean place of its cell's lowest points (its open top at its highest ones), not at the
  // cell's centre (2.5 cm is 1.4 deg at 1 m) nor at one of those points.
  float cell_m = 0.05f;
  // Points less than this above the ground are the ground (a VLP-16's floor ring scatters
  // a few cm on rough floors), and make no column.
  float ground_band_m = 0.10f;
  // Vertical spacing of the added points: at 1 m, 2.9 deg, which the view's gap fill joins
  // (DepthOptions::max_gap_deg 5 deg); columns 5 cm apart are joined sideways the same way.
  float step_m = 0.05f;
  // An open top goes up this much farther as the sensor sees it (its elevation from the
  // sensor): what lies just past the top ring is most likely the object going on; how far
  // it goes is unknown. Measured on the golden room (one VLP-16 rotation): 5 deg (as far as
  // the gap fill joins two samples) left the ring rig's panorama at 33.9 dB, 8 deg 37.6
  // (no more above), while the bird's-eye views lost past 10 deg (15 deg: -1.1 dB), where
  // columns reach above what they stand for. Never above max_height_m over the ground (one
  // storey).
  float open_top_deg = 8.f;
  float max_height_m = 3.f;
  // A flat cell (its points within flat_m of each other) with no point lower than
  // lowest_base_z, in it or the eight cells around it, makes no column: a ceiling or a sign
  // a ring grazes has nothing under it down to the floor, while anything standing on the
  // floor is hit near the sensor's own height by its middle rings, or, behind a lower object,
  // by several rings above it (the golden room's front wall behind a 1.5 m box: 0.44 m of it
  // in one cell; without `flat_m` those columns went and the panorama lost 2.2 dB).
  // complete_columns sets lowest_base_z 0.5 m above the highest of the rig's cameras and lidar.
  float lowest_base_z = INFINITY;
  float flat_m = 0.1f;
  // At most this many points added (the longest columns are a storey of 5 cm steps).
  size_t max_points = 1'000'000;
  // A column ends above where `see_through_rays` of the sensor's own rays (free_space.h)
  // passed under its lowest point, within `see_through_m` of it (1 cm: a VLP-16's 0.2 deg
  // steps are 7 mm apart at 2 m; wider, rays passing beside a box's side faces cut them).
  float see_through_m = 0.01f;
  int see_through_rays = 2;
  // Closed tops (the highest point of a cell the sensor saw over) joined across the cells
  // the rings skipped (flat_tops.h); its cell_m is this cell_m. max_gap_m 0: not joined.
  FlatTopOptions tops;
};

struct ColumnStats {
  size_t columns = 0;  // ground cells with points above the ground (overhead ones included)
  size_t overhead = 0;  // of them, cells above lowest_base_z: no column
  size_t added = 0;    // points added
  size_t open_tops = 0;
  size_t top_points = 0;  // of `added`, points joining closed tops (flat_tops.h)
  size_t seen_under = 0;  // columns cut short above where the sensor saw through
};

// The ground's height in a level frame (z up) as the most populated 2 cm slice of the
// points' heights below `below_z` (the robot's cameras, lidar: the floor is below them),
// when it holds at least `min_share` of those points; none otherwise (no ground seen).
std::optional<float> estimate_ground_z(const std::vector<Eigen::Vector3f>& points, float below_z,
                                       float min_share = 0.05f);

// Which points lie on the top of their sensor's field: `points` in the sensor's own frame
// (a spinning lidar's, z along its axis), 1 where a point's elevation is within
// `tolerance_deg` of the highest elevation among them (a VLP-16's top ring, +15 deg). None
// when the highest is below `lowest_top_deg`: robots' lidars reach +10 deg or more (VLP-16
// and VLP-32C +15, HDL-32E +10.7, OS1 +22.5), so the highest return lower than that is a
// ring under rings that saw the sky, and what it hit has a top the rings above passed over.
std::vector<uint8_t> top_of_field(const std::vector<Eigen::Vector3f>& points, float tolerance_deg = 0.5f,
                                  float lowest_top_deg = 10.f);

// Per point flags (`flags` below): on the top of its sensor's field (top_of_field's 1), and
// measured from the `sensor` given with them (SensorRays::kSeenFrom: a lidar's newest
// rotation; not a depth camera's points, nor an older rotation's, taken from elsewhere).
inline constexpr uint8_t kTopOfField = 1;

// The flags of one rotation of a spinning lidar, `points` in its own frame: each finite one
// seen from the sensor (SensorRays::kSeenFrom), those on its top ring kTopOfField too.
std::vector<uint8_t> lidar_flags(const std::vector<Eigen::Vector3f>& points);

// The added points, in the points' own frame: `points` in a level frame (z up) with the
// ground at ground_z; `flags` empty or one per point (above). Non-finite points are
// skipped. Closed tops are joined around `sensor` (the origin without one); columns end
// above where `sensor`'s own rays passed under them (free_space.h).
std::vector<Eigen::Vector3f> column_points(const std::vector<Eigen::Vector3f>& points,
                                           const std::vector<uint8_t>& flags, float ground_z,
                                           const ColumnOptions& options = {}, ColumnStats* stats = nullptr,
                                           const std::optional<Eigen::Vector3f>& sensor = std::nullopt);

// Where the sensor of points in `frame` stands, in the rig's robot frame, when they are a
// spinning lidar's whose top ring may be told (top_of_field): `frame` a frame of the rig that
// is neither the robot frame itself nor a camera's (a depth camera's points), within 5 m of
// the robot frame's origin (not a world frame). None else.
std::optional<Eigen::Vector3f> lidar_origin(const Rig& rig, const std::string& frame);

// The completion as the daemon's geometry, `omniview render --cloud` and the golden tests
// make it: `points` in the rig's robot frame (z up), the ground estimated below the lowest
// of its cameras and `lidar` (estimate_ground_z), open tops and seen-through space where
// `lidar` (the spinning lidar's place) is known and `flags` tell them (column_points). No
// ground seen: no completion.
struct Completion {
  std::vector<Eigen::Vector3f> points;
  std::optional<float> ground_z;
  ColumnStats stats;
};
Completion complete_columns(const Rig& rig, const std::vector<Eigen::Vector3f>& points,
                            const std::vector<uint8_t>& flags, const std::optional<Eigen::Vector3f>& lidar,
                            const ColumnOptions& options = {});

// The same in two steps, for a caller that completes the points later than it has the rig:
// what complete_columns takes of the rig (its cameras' and `lidar`'s lowest and highest
// heights), then the completion from those.
struct SensorHeights {
  float lowest = INFINITY, highest = -INFINITY;
};
SensorHeights sensor_heights(const Rig& rig, const std::optional<Eigen::Vector3f>& lidar);
Completion complete_columns(const SensorHeights& sensors, const std::vector<Eigen::Vector3f>& points,
                            const std::vector<uint8_t>& flags, const std::optional<Eigen::Vector3f>& lidar,
                            const ColumnOptions& options = {});

}  // namespace omniview

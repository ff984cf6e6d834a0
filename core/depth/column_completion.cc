#include "core/depth/column_completion.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace omniview {
namespace {

// A cell's lowest and highest points, each with the mean place of the points within
// kBandM of it (a ring's stretch across the cell): a column stands there, not at one point
// of the stretch. (At the first or last point of a ring in each cell, the columns of a
// crate's face 0.9 m from the front view stood 5 and 10 cm apart by turns, the wider gaps
// past what the view's gap fill joins: holes down the face, golden front view -1 dB.)
struct Column {
  static constexpr float kBandM = 0.02f;
  float z_min = 0, z_max = 0;
  Eigen::Vector2f low_sum{0, 0}, high_sum{0, 0};
  int low_n = 0, high_n = 0;
  bool open_top = false;  // a point of the top band lay on the top of its sensor's field
  bool any = false;
  Eigen::Vector2f xy_low() const { return low_sum / float(low_n); }
  Eigen::Vector2f xy_high() const { return high_sum / float(high_n); }
  void add(const Eigen::Vector3f& p, bool top) {
    const Eigen::Vector2f xy = p.head<2>();
    if (!any || p.z() < z_min - kBandM) {
      low_sum = xy, low_n = 1;
    } else if (p.z() <= z_min + kBandM) {
      low_sum += xy, ++low_n;
    }
    if (!any || p.z() > z_max + kBandM) {
      high_sum = xy, high_n = 1, open_top = top;
    } else if (p.z() >= z_max - kBandM) {
      high_sum += xy, ++high_n, open_top = open_top || top;
    }
    z_min = any ? std::min(z_min, p.z()) : p.z();
    z_max = any ? std::max(z_max, p.z()) : p.z();
    any = true;
  }
};

// Points farther out are no lidar's or depth camera's (and would overflow the cell indices).
constexpr float kFarthestM = 1000.f;
bool usable(const Eigen::Vector3f& p) { return p.allFinite() && p.cwiseAbs().maxCoeff() < kFarthestM; }

uint64_t cell_key(float x, float y, float inv_cell) {
  const auto ix = static_cast<int32_t>(std::floor(x * inv_cell));
  const auto iy = static_cast<int32_t>(std::floor(y * inv_cell));
  return (uint64_t(uint32_t(ix)) << 32) | uint32_t(iy);
}

}  // namespace

std::optional<float> estimate_ground_z(const std::vector<Eigen::Vector3f>& points, float below_z, float min_share) {
  constexpr float kSlice = 0.02f;
  std::unordered_map<int32_t, size_t> slices;
  size_t below = 0;
  for (const auto& p : points) {
    if (!usable(p) || !(p.z() < below_z)) continue;
    ++slices[static_cast<int32_t>(std::floor(p.z() / kSlice))];
    ++below;
  }
  if (below == 0) return std::nullopt;
  // The fullest slice; a floor seen at a slant spreads over two, so their pair counts.
  int32_t best = 0;
  size_t best_count = 0;
  for (const auto& [slice, count] : slices) {
    const auto next = slices.find(slice + 1);
    const size_t pair = count + (next == slices.end() ? 0 : next->second);
    if (pair > best_count || (pair == best_count && slice < best)) best = slice, best_count = pair;
  }
  if (double(best_count) < double(min_share) * double(below)) return std::nullopt;
  double sum = 0;  // the mean height of the pair's points
  for (const auto& p : points) {
    if (!usable(p) || !(p.z() < below_z)) continue;
    const auto slice = static_cast<int32_t>(std::floor(p.z() / kSlice));
    if (slice == best || slice == best + 1) sum += p.z();
  }
  return float(sum / double(best_count));
}

std::vector<uint8_t> top_of_field(const std::vector<Eigen::Vector3f>& points, float tolerance_deg,
                                  float lowest_top_deg) {
  std::vector<float> elevation(points.size(), -INFINITY);
  float highest = -INFINITY;
  for (size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    if (!p.allFinite()) continue;
    elevation[i] = std::atan2(p.z(), std::hypot(p.x(), p.y()));
    highest = std::max(highest, elevation[i]);
  }
  std::vector<uint8_t> top(points.size(), 0);
  if (!(highest >= lowest_top_deg * float(M_PI / 180))) return top;  // the top rings saw the sky
  const float threshold = highest - tolerance_deg * float(M_PI / 180);
  for (size_t i = 0; i < points.size(); ++i) top[i] = elevation[i] >= threshold && std::isfinite(elevation[i]);
  return top;
}

std::vector<uint8_t> lidar_flags(const std::vector<Eigen::Vector3f>& points) {
  std::vector<uint8_t> flags = top_of_field(points);
  for (size_t i = 0; i < points.size(); ++i) {
    if (points[i].allFinite()) flags[i] |= SensorRays::kSeenFrom;
  }
  return flags;
}

std::vector<Eigen::Vector3f> column_points(const std::vector<Eigen::Vector3f>& points,
                                           const std::vector<uint8_t>& flags, float ground_z,
                                           const ColumnOptions& options, ColumnStats* stats,
                                           const std::optional<Eigen::Vector3f>& sensor) {
  const float inv_cell = 1.f / options.cell_m;
  const float above = ground_z + options.ground_band_m;
  std::unordered_map<uint64_t, Column> columns;
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f& p = points[i];
    if (!usable(p) || !(p.z() > above)) continue;
    columns[cell_key(p.x(), p.y(), inv_cell)].add(p, !flags.empty() && (flags[i] & kTopOfField));
  }
  std::optional<SensorRays> rays;
  if (sensor && std::any_of(flags.begin(), flags.end(), [](uint8_t f) { return f & SensorRays::kSeenFrom; })) {
    rays.emplace(points, flags, *sensor);
  }
  std::vector<Eigen::Vector3f> added;
  ColumnStats s;
  s.columns = columns.size();
  const float ceiling = ground_z + options.max_height_m;
  // Overhead: flat, and nothing lower than lowest_base_z in the cell or the eight around it (a
  // wall's rings may fall into neighbouring cells, its top ring alone into one).
  const auto overhead = [&](uint64_t key) {
    const auto ix = int32_t(uint32_t(key >> 32)), iy = int32_t(uint32_t(key));
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        const auto near = columns.find((uint64_t(uint32_t(ix + dx)) << 32) | uint32_t(iy + dy));
        if (near != columns.end() && near->second.z_min <= options.lowest_base_z) return false;
      }
    }
    return true;
  };
  for (const auto& [key, c] : columns) {
    if (c.z_min > options.lowest_base_z && c.z_max - c.z_min < options.flat_m && overhead(key)) {
      ++s.overhead;
      continue;
    }
    if (added.size() >= options.max_points) break;
    // Down to the ground (the ground itself included: the object's foot), or to just above
    // where the sensor saw through under it.
    const Eigen::Vector2f low = c.xy_low(), high = c.xy_high();
    float bottom = ground_z;
    if (const auto through = rays ? rays->highest_crossing(low, c.z_min, ground_z + 0.5f * options.step_m,
                                                           options.see_through_m, options.see_through_rays)
                                  : std::nullopt) {
      bottom = std::min(c.z_min, *through + options.step_m);
      ++s.seen_under;
    }
    // From the lowest point's own height: a view takes each added point as the stretch
    // down to the next (range_splat.h's splat_stretches).
    for (float z = c.z_min; z > bottom - 0.5f * options.step_m; z -= options.step_m) {
      added.emplace_back(low.x(), low.y(), std::max(z, bottom));
    }
    if (c.open_top && sensor) {
      ++s.open_tops;
      const float d = (high - sensor->head<2>()).norm();
      const float elevation = std::atan2(c.z_max - sensor->z(), d) + options.open_top_deg * float(M_PI / 180);
      const float top = std::min(sensor->z() + d * std::tan(std::min(elevation, float(M_PI / 2.5))), ceiling);
      for (float z = c.z_max + options.step_m; z <= top; z += options.step_m) {
        added.emplace_back(high.x(), high.y(), z);
      }
    }
  }
  // Closed tops joined across the cells the rings skipped: not the open ones (what is
  // above them is unknown) nor overhead ones (a ceiling's rings are its own surface).
  std::vector<CellTop> tops;
  for (const auto& [key, c] : columns) {
    if (c.open_top || (c.z_min > options.lowest_base_z && c.z_max - c.z_min < options.flat_m && overhead(key))) continue;
    tops.push_back({int32_t(uint32_t(key >> 32)), int32_t(uint32_t(key)), c.z_max});
  }
  FlatTopOptions top_options = options.tops;
  top_options.cell_m = options.cell_m;
  if (top_options.max_gap_m > 0.f && added.size() < options.max_points) {
    const Eigen::Vector2f centre = sensor ? Eigen::Vector2f(sensor->head<2>()) : Eigen::Vector2f::Zero();
    const std::vector<Eigen::Vector3f> joined = flat_top_points(points, tops, centre, top_options);
    const size_t n = std::min(joined.size(), options.max_points - added.size());
    added.insert(added.end(), joined.begin(), joined.begin() + n);
    s.top_points = n;
  }
  s.added = added.size();
  if (stats) *stats = s;
  return added;
}

std::optional<Eigen::Vector3f> lidar_origin(const Rig& rig, const std::string& frame) {
  if (frame == rig.default_frame()) return std::nullopt;
  for (const Camera& camera : rig.cameras()) {
    if (camera.name == frame) return std::nullopt;
  }
  const auto T_robot_frame = rig.frames().try_lookup(rig.default_frame(), frame);
  // A sensor rides on the robot: a frame farther out is a world frame (odom, a map).
  constexpr double kOnTheRobotM = 5.0;
  if (!T_robot_frame || T_robot_frame->translation().norm() > kOnTheRobotM) return std::nullopt;
  return T_robot_frame->translation().cast<float>();
}

SensorHeights sensor_heights(const Rig& rig, const std::optional<Eigen::Vector3f>& lidar) {
  SensorHeights h;
  if (lidar) h.lowest = h.highest = lidar->z();
  for (size_t i = 0; i < rig.cameras().size(); ++i) {
    const float z = float(rig.camera_pose(rig.default_frame(), i).translation().z());
    h.lowest = std::min(h.lowest, z);
    h.highest = std::max(h.highest, z);
  }
  return h;
}

Completion complete_columns(const SensorHeights& sensors, const std::vector<Eigen::Vector3f>& points,
                            const std::vector<uint8_t>& flags, const std::optional<Eigen::Vector3f>& lidar,
                            const ColumnOptions& options) {
  Completion c;
  c.ground_z = estimate_ground_z(points, sensors.lowest);
  if (!c.ground_z) return c;
  ColumnOptions bounded = options;
  if (std::isfinite(sensors.highest)) bounded.lowest_base_z = std::min(options.lowest_base_z, sensors.highest + 0.5f);
  c.points = column_points(points, flags, *c.ground_z, bounded, &c.stats, lidar);
  return c;
}

Completion complete_columns(const Rig& rig, const std::vector<Eigen::Vector3f>& points,
                            const std::vector<uint8_t>& flags, const std::optional<Eigen::Vector3f>& lidar,
                            const ColumnOptions& options) {
  return complete_columns(sensor_heights(rig, lidar), points, flags, lidar, options);
}

}  // namespace omniview

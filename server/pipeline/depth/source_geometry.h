// The geometry a source measures, for its views with `depth: measured`: its recent lidar
// clouds in the rig's robot frame, several accumulated with the robot's motion and aged
// out, as one set of points as of the newest cloud.
//
// Why accumulate: one VLP-16 rotation is 16 rings 2 deg apart (10 cm at 3 m, 35 cm at
// 10 m); a few rotations, each moved to where the robot is now, fill between the rings of
// a robot that moves or turns, and cost a still robot nothing but points. Why age out:
// what moved (a person, a door) must leave the surface within a moment.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/cloud/point_cloud.h"
#include "core/cloud/trajectory.h"
#include "core/depth/camera_occluders.h"
#include "core/depth/column_completion.h"
#include "core/rig/rig.h"

namespace omniview {

struct GeometryOptions {
  // Clouds older than this (capture time, behind the newest) leave the set: 5 rotations of
  // a 10 Hz lidar. Longer smears what moves; shorter leaves the rings apart.
  std::chrono::milliseconds keep{500};
  // Depth images (a robot's depth cameras, asked for every 0.5 s): kept for two of them.
  std::chrono::milliseconds keep_depth_images{1000};
  // The most points kept (the oldest clouds go first): ~10 rotations of a VLP-16, 1.5
  // rotations of a 32-beam lidar, and what a depth update of a 1024x512 view handles in
  // tens of milliseconds (bench/depth_bench).
  size_t max_points = 300000;
};

// The columns completing a snapshot's points (core/depth/column_completion.h), made when a
// depth view's update first asks for them, on its own thread and within its duty cycle,
// not at every cloud's arrival: on 300 k points they cost ~12 ms, which at a 10 Hz lidar
// and 2 Hz depth images took a seventh of a core whether or not a view took them.
class LazyCompletion {
 public:
  // `flags`: per point, as column_points takes them (empty: none told).
  LazyCompletion(std::shared_ptr<const std::vector<Eigen::Vector3f>> points, std::vector<uint8_t> flags,
                 std::optional<Eigen::Vector3f> lidar, SensorHeights sensors)
      : points_(std::move(points)), flags_(std::move(flags)), lidar_(lidar), sensors_(sensors) {}
  // Made once, by the first caller; the others wait for it.
  const Completion& get() const;

 private:
  std::shared_ptr<const std::vector<Eigen::Vector3f>> points_;
  std::vector<uint8_t> flags_;
  std::optional<Eigen::Vector3f> lidar_;
  SensorHeights sensors_;
  mutable std::once_flag once_;
  mutable Completion completion_;
};

// Geometry a depth view stands on at most this old: a changed view or one watched again
// takes the source's geometry only if it is this recent, and one whose geometry grew older
// (nobody watched, the lidar stopped) returns to its fixed surface until new geometry comes.
// Counted from when the geometry was ready (its points moved into the robot's frame), not
// from its cloud's arrival: on a starved machine the accumulation alone took seconds under
// a sanitizer, and a window that counted it dropped every geometry unused, so a view never
// stood on measured depth (CI, stop 42).
inline constexpr std::chrono::seconds kFreshGeometry{2};

inline bool fresh_geometry(std::chrono::steady_clock::time_point ready, std::chrono::steady_clock::time_point now) {
  return now - ready < kFreshGeometry;
}

// Points as of one moment, shared with every depth view of the source.
struct GeometrySnapshot {
  uint64_t version = 0;  // increases with every cloud added
  std::shared_ptr<const std::vector<Eigen::Vector3f>> points;  // in `frame`, finite
  // What completes them where a sensor's field cut objects short (columns down to the
  // ground and past a lidar's top ring: core/depth/column_completion.h), in `frame`.
  std::shared_ptr<const LazyCompletion> completion;
  std::string frame;                                           // the rig's default (robot) frame
  std::chrono::system_clock::time_point stamp;                 // the newest cloud's capture time
  std::chrono::steady_clock::time_point arrival;               // when the daemon had its newest cloud
  std::chrono::steady_clock::time_point ready;                 // when this snapshot was made of it
  size_t clouds = 0;                                           // accumulated into `points`
};

class SourceGeometry {
 public:
  explicit SourceGeometry(GeometryOptions options = {}) : options_(options) {}

  // Adds a cloud delivered with `rig` (its points in one of the rig's frames, or a camera's
  // optical frame for a depth camera's points) and the robot's recent motion (null: the
  // robot is taken to be still). A cloud whose frame the rig does not know, or with no
  // finite point, is counted and skipped (message()).
  void add(const PointCloud& cloud, const Rig& rig, const Trajectory* motion,
           std::chrono::steady_clock::time_point arrival);
  // Several at once (a frame set's lidar cloud and depth images): one new snapshot.
  void add(const std::vector<const PointCloud*>& clouds, const Rig& rig, const Trajectory* motion,
           std::chrono::steady_clock::time_point arrival);

  std::optional<GeometrySnapshot> latest() const;
  // Why the last cloud was skipped ("" when it was not), and how many were.
  std::string message() const;
  uint64_t skipped() const;

  // Each camera's range-image layout for occlusion (core/depth/camera_occluders.h), made
  // once per rig and shared by the source's depth views; what it returns keeps `rig` alive.
  std::shared_ptr<const CameraRangeImages> range_images(const std::shared_ptr<const Rig>& rig, double cell_deg);
  // The cameras' occluders of `snapshot`'s points (core/depth/camera_occluders.h's
  // points_occlusion, in the rig's default frame): the same for every depth view of the
  // source, so made once per geometry version and rig and shared (two watched depth views
  // made them twice).
  std::shared_ptr<const Occlusion> occluders(const GeometrySnapshot& snapshot, const std::shared_ptr<const Rig>& rig,
                                             const ViewOcclusionOptions& options);

 private:
  struct Cloud {
    std::chrono::system_clock::time_point stamp;
    std::chrono::milliseconds keep;
    std::vector<Eigen::Vector3f> points;  // in the robot frame at `stamp`
    std::vector<uint8_t> flags;           // per point: lidar_flags (empty: no lidar's, or none told)
    std::optional<Eigen::Vector3f> lidar; // the lidar's place in the robot frame at `stamp`
  };
  bool take(const PointCloud& cloud, const Rig& rig);  // false: skipped
  void rebuild(const Rig& rig, const Trajectory* motion, std::chrono::steady_clock::time_point arrival);

  const GeometryOptions options_;
  mutable std::mutex mutex_;
  std::deque<Cloud> clouds_;  // by arrival, oldest first
  std::optional<GeometrySnapshot> latest_;
  std::string message_;
  uint64_t skipped_ = 0;
  uint64_t version_ = 0;
  std::shared_ptr<const Rig> range_rig_;
  std::shared_ptr<const CameraRangeImages> range_images_;
  std::mutex occluders_mutex_;  // apart from mutex_: making them takes milliseconds
  uint64_t occluders_version_ = 0;
  std::shared_ptr<const Rig> occluders_rig_;
  std::shared_ptr<const Occlusion> occluders_;
};

}  // namespace omniview

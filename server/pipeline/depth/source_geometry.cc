#include "server/pipeline/depth/source_geometry.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace omniview {

void SourceGeometry::add(const PointCloud& cloud, const Rig& rig, const Trajectory* motion,
                         std::chrono::steady_clock::time_point arrival) {
  add({&cloud}, rig, motion, arrival);
}

void SourceGeometry::add(const std::vector<const PointCloud*>& clouds, const Rig& rig, const Trajectory* motion,
                         std::chrono::steady_clock::time_point arrival) {
  bool added = false;
  for (const PointCloud* cloud : clouds) added = take(*cloud, rig) || added;
  if (added) rebuild(rig, motion, arrival);
}

bool SourceGeometry::take(const PointCloud& cloud, const Rig& rig) {
  const std::string robot = rig.default_frame();
  // A depth camera's points are in its optical frame: the rig's camera pose, not the frame
  // link of the same name.
  std::optional<Pose> T_robot_cloud;
  bool from_camera = false;
  for (size_t i = 0; i < rig.cameras().size(); ++i) {
    if (rig.cameras()[i].name == cloud.frame) T_robot_cloud = rig.camera_pose(robot, i), from_camera = true;
  }
  if (!T_robot_cloud) T_robot_cloud = rig.frames().try_lookup(robot, cloud.frame);
  Cloud entry;
  entry.stamp = cloud.stamp;
  entry.keep = from_camera ? options_.keep_depth_images : options_.keep;
  if (T_robot_cloud) {
    const Eigen::Matrix3f R = T_robot_cloud->linear().cast<float>();
    const Eigen::Vector3f t = T_robot_cloud->translation().cast<float>();
    entry.points.reserve(cloud.points.size());
    std::vector<Eigen::Vector3f> finite;  // in the cloud's own frame, for its top ring and rays
    finite.reserve(cloud.points.size());
    for (const auto& p : cloud.points) {
      if (p.allFinite()) entry.points.push_back(R * p + t), finite.push_back(p);
    }
    if (!from_camera) entry.lidar = lidar_origin(rig, cloud.frame);
    if (entry.lidar) entry.flags = lidar_flags(finite);
  }
  std::lock_guard lock(mutex_);
  if (!T_robot_cloud || entry.points.empty()) {
    ++skipped_;
    message_ = !T_robot_cloud ? "points in frame '" + cloud.frame + "', which is not connected to the rig's '" +
                                    robot + "': skipped"
                              : "a cloud of points with no finite point: skipped";
    return false;
  }
  message_.clear();
  clouds_.push_back(std::move(entry));
  return true;
}

void SourceGeometry::rebuild(const Rig& rig, const Trajectory* motion, std::chrono::steady_clock::time_point arrival) {
  std::lock_guard lock(mutex_);
  // Age out by capture time behind the newest, then keep within the point budget.
  auto newest = clouds_.back().stamp;
  for (const auto& c : clouds_) newest = std::max(newest, c.stamp);
  std::erase_if(clouds_, [&](const Cloud& c) { return newest - c.stamp > c.keep; });
  size_t total = 0;
  for (const auto& c : clouds_) total += c.points.size();
  while (clouds_.size() > 1 && total > options_.max_points) {
    total -= clouds_.front().points.size();
    clouds_.pop_front();
  }

  // Every cloud moved to where the robot is at the newest one's time (odometry between
  // the two; none known: the robot is taken to be still).
  auto points = std::make_shared<std::vector<Eigen::Vector3f>>();
  points->reserve(std::min(total, options_.max_points));
  // Per point: on a lidar's top ring, and seen from the newest lidar cloud's place (the
  // older rotations' rays started where the robot stood then); empty when no cloud told.
  const bool told = std::any_of(clouds_.begin(), clouds_.end(), [](const Cloud& c) { return !c.flags.empty(); });
  std::vector<uint8_t> flags;
  if (told) flags.reserve(points->capacity());
  const Cloud* newest_lidar = nullptr;
  for (const auto& c : clouds_) {
    if (c.lidar && (!newest_lidar || c.stamp >= newest_lidar->stamp)) newest_lidar = &c;
  }
  std::optional<Eigen::Vector3f> lidar;  // the newest lidar cloud's, moved to now
  for (const auto& c : clouds_) {
    const Pose T_now_then = motion ? motion->relative(newest, c.stamp) : Pose::Identity();
    const Eigen::Matrix3f R = T_now_then.linear().cast<float>();
    const Eigen::Vector3f t = T_now_then.translation().cast<float>();
    // The newest cloud alone may exceed the budget: keep an even subset of it.
    const size_t step = c.points.size() > options_.max_points
                            ? (c.points.size() + options_.max_points - 1) / options_.max_points
                            : 1;
    const uint8_t keep = &c == newest_lidar ? 0xff : uint8_t(~SensorRays::kSeenFrom);
    for (size_t i = 0; i < c.points.size(); i += step) {
      points->push_back(R * c.points[i] + t);
      if (told) flags.push_back(c.flags.empty() ? 0 : c.flags[i] & keep);
    }
    if (&c == newest_lidar) lidar = R * *c.lidar + t;
  }
  GeometrySnapshot snapshot;
  snapshot.version = ++version_;
  snapshot.completion = std::make_shared<const LazyCompletion>(points, std::move(flags), lidar, sensor_heights(rig, lidar));
  snapshot.points = std::move(points);
  snapshot.frame = rig.default_frame();
  snapshot.stamp = newest;
  snapshot.arrival = arrival;
  snapshot.ready = std::chrono::steady_clock::now();
  snapshot.clouds = clouds_.size();
  latest_ = std::move(snapshot);
}

const Completion& LazyCompletion::get() const {
  std::call_once(once_, [this] { completion_ = complete_columns(sensors_, *points_, flags_, lidar_); });
  return completion_;
}

std::optional<GeometrySnapshot> SourceGeometry::latest() const {
  std::lock_guard lock(mutex_);
  return latest_;
}

std::string SourceGeometry::message() const {
  std::lock_guard lock(mutex_);
  return message_;
}

uint64_t SourceGeometry::skipped() const {
  std::lock_guard lock(mutex_);
  return skipped_;
}

std::shared_ptr<const CameraRangeImages> SourceGeometry::range_images(const std::shared_ptr<const Rig>& rig,
                                                                      double cell_deg) {
  std::lock_guard lock(mutex_);
  if (rig != range_rig_) {
    // CameraRangeImages refers to its rig: whoever holds one holds the rig too.
    struct Held {
      std::shared_ptr<const Rig> rig;
      CameraRangeImages images;
    };
    auto held = std::make_shared<const Held>(Held{rig, CameraRangeImages(*rig, cell_deg)});
    range_images_ = std::shared_ptr<const CameraRangeImages>(held, &held->images);
    range_rig_ = rig;
  }
  return range_images_;
}

std::shared_ptr<const Occlusion> SourceGeometry::occluders(const GeometrySnapshot& snapshot,
                                                           const std::shared_ptr<const Rig>& rig,
                                                           const ViewOcclusionOptions& options) {
  const auto cameras = range_images(rig, options.cell_deg);
  std::lock_guard lock(occluders_mutex_);
  if (!occluders_ || occluders_version_ != snapshot.version || occluders_rig_ != rig) {
    const auto T_robot_points = rig->frames().try_lookup(rig->default_frame(), snapshot.frame);
    if (!T_robot_points) {
      throw std::invalid_argument("the geometry's frame '" + snapshot.frame + "' is not connected to the rig's '" +
                                  rig->default_frame() + "'");
    }
    occluders_ = std::make_shared<const Occlusion>(
        points_occlusion(*cameras, *snapshot.points, rig->default_frame(), *T_robot_points, options,
                         snapshot.completion ? &snapshot.completion->get().points : nullptr));
    occluders_version_ = snapshot.version;
    occluders_rig_ = rig;
  }
  return occluders_;
}

}  // namespace omniview

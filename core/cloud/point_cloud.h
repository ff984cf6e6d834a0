// A point cloud as sources deliver it and files store it: points in one named frame, one
// capture stamp, and optional per-point fields (colour, intensity, time, ring, and the
// colourer's flags and camera index). An optional field is either empty or has one entry
// per point.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/rig/camera_index.h"

namespace omniview {

// Bad cloud data (a file, a packet): the message names the file or source and the field.
class CloudFormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Per-point flags the colourer and the self-filter write (PointCloud::flags).
namespace cloud_flags {
inline constexpr uint8_t kColoured = 1;  // took its colour from at least one camera
inline constexpr uint8_t kOccluded = 2;  // a camera would image it, but a nearer surface hides it
inline constexpr uint8_t kSelf = 4;      // on the robot's own body (self-filter)
}  // namespace cloud_flags

// PointCloud::camera for a point no camera coloured: kNoCamera (core/rig/camera_index.h).

struct PointCloud {
  using Rgb = std::array<uint8_t, 3>;  // R, G, B (the order PLY and PCD write)

  std::string frame;                               // frame the points are given in
  std::chrono::system_clock::time_point stamp{};   // capture time (of time offset 0)

  std::vector<Eigen::Vector3f> points;  // metres; non-finite entries are "no return"
  std::vector<Rgb> rgb;                 // optional
  std::vector<float> intensity;         // optional, as the sensor reports it
  std::vector<float> time;              // optional: seconds after `stamp` each point was measured
  std::vector<uint16_t> ring;           // optional: laser index (VLP-16: 0..15)
  std::vector<uint8_t> flags;           // optional: cloud_flags bits
  std::vector<uint8_t> camera;          // optional: rig camera index a colour came from, kNoCamera

  size_t size() const { return points.size(); }
  bool empty() const { return points.empty(); }

  // Names of the fields present, in file order: x y z, then rgb, intensity, time, ring,
  // flags, camera as present.
  std::vector<std::string> field_names() const;

  // Throws std::invalid_argument naming `what` and the field whose length is neither 0
  // nor size().
  void check(const std::string& what) const;

  // Keeps the points where keep[i] is true, in order, with all their fields.
  void filter(const std::vector<bool>& keep);
  // Appends `other`'s points (its fields must be present exactly where this cloud's are,
  // unless this cloud is empty, which then becomes a copy). `other`'s times are shifted to
  // this cloud's stamp.
  void append(const PointCloud& other);
};

}  // namespace omniview

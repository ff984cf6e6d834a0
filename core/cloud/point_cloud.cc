#include "core/cloud/point_cloud.h"

namespace omniview {
namespace {

template <typename V>
void keep_entries(V& v, const std::vector<bool>& keep) {
  if (v.empty()) return;
  size_t out = 0;
  for (size_t i = 0; i < v.size(); ++i) {
    if (keep[i]) v[out++] = v[i];
  }
  v.resize(out);
}

template <typename V>
void check_field(const V& v, size_t n, const std::string& what, const char* name) {
  if (!v.empty() && v.size() != n) {
    throw std::invalid_argument(what + ": field '" + name + "' has " + std::to_string(v.size()) +
                                " entries for " + std::to_string(n) + " points");
  }
}

template <typename V>
void append_field(V& v, const V& other, size_t old_size, const char* name) {
  if (v.empty() != other.empty() && old_size > 0) {
    throw std::invalid_argument(std::string("cannot append clouds: field '") + name + "' is in only one of them");
  }
  v.insert(v.end(), other.begin(), other.end());
}

}  // namespace

std::vector<std::string> PointCloud::field_names() const {
  std::vector<std::string> names{"x", "y", "z"};
  if (!rgb.empty()) names.insert(names.end(), {"r", "g", "b"});
  if (!intensity.empty()) names.push_back("intensity");
  if (!time.empty()) names.push_back("time");
  if (!ring.empty()) names.push_back("ring");
  if (!flags.empty()) names.push_back("flags");
  if (!camera.empty()) names.push_back("camera");
  return names;
}

void PointCloud::check(const std::string& what) const {
  const size_t n = points.size();
  check_field(rgb, n, what, "rgb");
  check_field(intensity, n, what, "intensity");
  check_field(time, n, what, "time");
  check_field(ring, n, what, "ring");
  check_field(flags, n, what, "flags");
  check_field(camera, n, what, "camera");
}

void PointCloud::filter(const std::vector<bool>& keep) {
  check("cloud");
  if (keep.size() != points.size()) throw std::invalid_argument("PointCloud::filter: mask size differs from the cloud's");
  keep_entries(points, keep);
  keep_entries(rgb, keep);
  keep_entries(intensity, keep);
  keep_entries(time, keep);
  keep_entries(ring, keep);
  keep_entries(flags, keep);
  keep_entries(camera, keep);
}

void PointCloud::append(const PointCloud& other) {
  const size_t old_size = points.size();
  if (old_size == 0) {  // an empty cloud takes the other's stamp and fields
    const std::string saved_frame = frame;
    *this = other;
    if (frame.empty()) frame = saved_frame;
    return;
  }
  points.insert(points.end(), other.points.begin(), other.points.end());
  append_field(rgb, other.rgb, old_size, "rgb");
  append_field(intensity, other.intensity, old_size, "intensity");
  const float shift = std::chrono::duration<float>(other.stamp - stamp).count();
  if (!time.empty() || !other.time.empty() || shift != 0.0f) {
    time.resize(old_size, 0.0f);
    for (size_t i = 0; i < other.size(); ++i) time.push_back((other.time.empty() ? 0.0f : other.time[i]) + shift);
  }
  append_field(ring, other.ring, old_size, "ring");
  append_field(flags, other.flags, old_size, "flags");
  append_field(camera, other.camera, old_size, "camera");
}

}  // namespace omniview

#include "core/depth/free_space.h"

#include <algorithm>
#include <cmath>
#include <functional>

namespace omniview {

namespace {

// atan2 within 0.004 rad (0.22 deg, under half a bin) at a fraction of its cost: a
// polynomial for atan on [-1, 1] (Rajan et al., 2006) and the octant's symmetry. Rays are
// binned and looked up by the same function, and the lookup takes a bin more each side.
float fast_atan2(float y, float x) {
  const float ax = std::abs(x), ay = std::abs(y);
  if (ax == 0.f && ay == 0.f) return 0.f;
  const bool steep = ay > ax;
  const float t = steep ? ax / ay : ay / ax;
  float a = t * (float(M_PI / 4) + 0.273f * (1.f - t));
  if (steep) a = float(M_PI / 2) - a;
  if (x < 0.f) a = float(M_PI) - a;
  return y < 0.f ? -a : a;
}

}  // namespace

int SensorRays::bin_of(const Eigen::Vector2f& d) {
  const int b = static_cast<int>(std::floor((fast_atan2(d.y(), d.x()) + float(M_PI)) * (kBins / (2 * float(M_PI)))));
  return ((b % kBins) + kBins) % kBins;
}

SensorRays::SensorRays(const std::vector<Eigen::Vector3f>& points, const std::vector<uint8_t>& flags,
                       const Eigen::Vector3f& sensor)
    : sensor_(sensor), bin_start_(kBins + 1, 0) {
  if (flags.size() != points.size() || !sensor.allFinite()) return;
  // Counting sort by bin: one flat array, no allocation per bin.
  std::vector<int> bin(points.size(), -1);
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f& p = points[i];
    if (!(flags[i] & kSeenFrom) || !p.allFinite()) continue;
    const Eigen::Vector2f d = p.head<2>() - sensor.head<2>();
    if (!(d.squaredNorm() > 1e-6f)) continue;
    bin[i] = bin_of(d);
    ++bin_start_[bin[i] + 1];
  }
  for (int b = 0; b < kBins; ++b) bin_start_[b + 1] += bin_start_[b];
  count_ = bin_start_[kBins];
  rays_.resize(count_);
  std::vector<uint32_t> next(bin_start_.begin(), bin_start_.end() - 1);
  for (size_t i = 0; i < points.size(); ++i) {
    if (bin[i] < 0) continue;
    const Eigen::Vector2f d = points[i].head<2>() - sensor.head<2>();
    const float range = d.norm();
    rays_[next[bin[i]]++] = {d / range, range, (points[i].z() - sensor.z()) / range};
  }
}

std::optional<float> SensorRays::highest_crossing(const Eigen::Vector2f& xy, float below_z, float floor_z,
                                                  float radius, int min_rays) const {
  if (count_ == 0) return std::nullopt;
  const Eigen::Vector2f to = xy - sensor_.head<2>();
  const float d = to.norm();
  if (!(d > radius)) return std::nullopt;  // at the sensor's own foot: no ray to judge by
  // The bins a ray passing within `radius` of `xy` may end in (it ends farther out, so its
  // azimuth differs from xy's by at most asin(radius / d)).
  const float half = std::asin(std::min(1.f, radius / d));
  const int centre = bin_of(to);
  const int reach = 1 + static_cast<int>(std::ceil(half * (kBins / (2 * float(M_PI)))));  // +1: fast_atan2's error
  const int first = centre - reach;
  const int span = std::min(2 * reach, kBins - 1);
  // The min_rays highest crossings, highest first: one stray return (a mixed pixel at an
  // edge) does not lower what stands there by itself.
  std::vector<float> highest;
  for (int k = 0; k <= span; ++k) {
    const int b = ((first + k) % kBins + kBins) % kBins;
    for (uint32_t r = bin_start_[b]; r < bin_start_[b + 1]; ++r) {
      const Ray& ray = rays_[r];
      if (ray.range <= d + radius) continue;  // ends before the line, or on what stands there
      const float along = ray.dir.dot(to);
      const float across = std::abs(ray.dir.x() * to.y() - ray.dir.y() * to.x());
      if (across > radius || along <= 0.f) continue;
      const float h = sensor_.z() + ray.slope * along;
      if (h >= below_z || h <= floor_z) continue;
      if (int(highest.size()) < min_rays) {
        highest.insert(std::upper_bound(highest.begin(), highest.end(), h, std::greater<float>()), h);
      } else if (h > highest.back()) {
        highest.pop_back();
        highest.insert(std::upper_bound(highest.begin(), highest.end(), h, std::greater<float>()), h);
      }
    }
  }
  if (min_rays < 1 || int(highest.size()) < min_rays) return std::nullopt;
  return highest.back();
}

}  // namespace omniview

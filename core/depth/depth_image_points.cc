#include "core/depth/depth_image_points.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/camera/camera_model.h"

namespace omniview {

std::vector<Eigen::Vector3f> depth_image_points(const DepthImage& image, const Camera& camera, int step,
                                                double max_range_m) {
  const auto pixels = static_cast<size_t>(camera.width) * static_cast<size_t>(camera.height);
  if (image.data.size() != 2 * pixels) {
    throw std::invalid_argument("depth image of camera '" + camera.name + "': " + std::to_string(image.data.size()) +
                                " bytes for " + std::to_string(pixels) + " 16-bit pixels");
  }
  if (!(image.scale > 0) || !std::isfinite(image.scale)) {
    throw std::invalid_argument("depth image of camera '" + camera.name + "': no usable scale (" +
                                std::to_string(image.scale) + ")");
  }
  step = std::max(1, step);
  std::vector<Eigen::Vector3f> points;
  points.reserve(pixels / size_t(step * step));
  const uint8_t* bytes = image.data.data();
  for (int v = 0; v < camera.height; v += step) {
    for (int u = 0; u < camera.width; u += step) {
      const size_t i = size_t(v) * camera.width + u;
      const unsigned raw = bytes[2 * i] | (unsigned(bytes[2 * i + 1]) << 8);
      if (raw == 0) continue;
      const double z = raw / image.scale;
      if (z > max_range_m) continue;
      Eigen::Vector3d ray;
      if (!unproject(camera.model, Eigen::Vector2d(u, v), ray) || !(ray.z() > 0)) continue;
      points.push_back((ray * (z / ray.z())).cast<float>());
    }
  }
  return points;
}

}  // namespace omniview

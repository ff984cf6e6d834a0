#include "spot_adapter/mock/sensors/camera_depth.h"

#include <cmath>
#include <cstring>

#include <opencv2/core/utility.hpp>

#include "core/camera/camera_model.h"
#include "spot_adapter/mock/sensors/render_cache.h"

namespace omniview::spot_mock {

cv::Mat render_depth_mm(const synthetic::Scene& scene, const Rig& rig, size_t index, const std::string& world_frame,
                        double range_m) {
  const Camera& cam = rig.cameras().at(index);
  const Pose T_world_cam = rig.camera_pose(world_frame, index);
  // Hoisted: the depth along the optical axis is the hit's offset from the centre along the
  // axis; an Isometry inverse per pixel made this render 25x the pictures' time per ray
  // under AddressSanitizer (40 s for five cameras).
  const Vec3 centre = T_world_cam.translation();
  const Vec3 axis = T_world_cam.linear().col(2);
  const Eigen::Matrix3d R = T_world_cam.linear();
  const double cos_half_fov = cam.fov_deg > 0 ? std::cos(cam.fov_deg * M_PI / 360) : -2.0;
  cv::Mat out(cam.height, cam.width, CV_16UC1, cv::Scalar(0));
  cv::parallel_for_(cv::Range(0, cam.height), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      uint16_t* row = out.ptr<uint16_t>(v);
      for (int u = 0; u < cam.width; ++u) {
        if (!cam.mask.empty() && cam.mask.at<uint8_t>(v, u) <= 127) continue;  // as the pictures
        Vec3 ray;  // in the camera's optical frame (z forward)
        if (!unproject(cam.model, Vec2(u, v), ray) || ray.z() <= 0 || ray.normalized().z() < cos_half_fov) continue;
        const auto hit = scene.intersect(centre, R * ray);
        if (!hit) continue;
        const double z = (hit->point - centre).dot(axis);
        if (!(z > 0) || z > range_m) continue;
        row[u] = static_cast<uint16_t>(std::lround(z * kDepthScale));
      }
    }
  });
  return out;
}

CameraDepths::CameraDepths(SceneKind scene, const Rig& rig, const std::string& render_cache)
    : scene_(scene), rig_(rig), raw_(rig.cameras().size()), rendered_(rig.cameras().size(), false) {
  if (render_cache.empty()) return;
  const RenderCache cache(render_cache, std::string("depth scene=") + to_string(scene) +
                                            " range_mm=" + std::to_string(std::lround(kDepthRangeM * 1000)));
  auto stored = cache.load_bytes();
  if (!stored || stored->size() != raw_.size()) {
    stored.emplace();
    const synthetic::Scene world = make_scene(scene_);  // made once: its textures are costly under the sanitizers
    for (size_t c = 0; c < raw_.size(); ++c) stored->push_back(render(world, c));
    cache.store_bytes(*stored);
  }
  raw_ = std::move(*stored);
  rendered_.assign(raw_.size(), true);
}

std::string CameraDepths::render(const synthetic::Scene& world, size_t camera) const {
  const cv::Mat depth = render_depth_mm(world, rig_, camera, kWorldFrame);
  std::string bytes(depth.total() * 2, '\0');
  const uint16_t* values = depth.ptr<uint16_t>();  // continuous: just made
  for (size_t p = 0; p < depth.total(); ++p) {  // little-endian on any host
    bytes[2 * p] = static_cast<char>(values[p] & 0xff);
    bytes[2 * p + 1] = static_cast<char>(values[p] >> 8);
  }
  return bytes;
}

const std::string& CameraDepths::raw(size_t camera) {
  std::lock_guard lock(mutex_);
  if (!rendered_.at(camera)) {
    raw_[camera] = render(make_scene(scene_), camera);
    rendered_[camera] = true;
  }
  return raw_[camera];
}

}  // namespace omniview::spot_mock

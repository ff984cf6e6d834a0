#include "core/synthetic/render.h"

#include <cmath>

#include <opencv2/core.hpp>

namespace omniview::synthetic {

cv::Mat render_camera(const Scene& scene, const Rig& rig, size_t index, const std::string& world_frame,
                      const RenderOptions& options) {
  const Camera& cam = rig.cameras().at(index);
  const Pose T_world_cam = rig.camera_pose(world_frame, index);
  const int n = std::max(1, options.supersample);
  const double cos_half_fov = cam.fov_deg > 0 ? std::cos(cam.fov_deg * M_PI / 360) : -2.0;
  cv::Mat out(cam.height, cam.width, options.grey ? CV_8UC1 : CV_8UC3, cv::Scalar::all(0));
  cv::parallel_for_(cv::Range(0, cam.height), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      for (int u = 0; u < cam.width; ++u) {
        if (!cam.mask.empty() && cam.mask.at<uint8_t>(v, u) <= 127) continue;
        Vec3 sum = Vec3::Zero();
        for (int sy = 0; sy < n; ++sy) {
          for (int sx = 0; sx < n; ++sx) {
            // Sub-pixel offsets spread over the pixel's area around its centre.
            const Vec2 uv(u + (sx + 0.5) / n - 0.5, v + (sy + 0.5) / n - 0.5);
            Vec3 ray;
            if (!unproject(cam.model, uv, ray) || ray.normalized().z() < cos_half_fov) continue;
            const auto hit = scene.intersect(T_world_cam.translation(), T_world_cam.linear() * ray);
            if (hit) sum += scene.colour(*hit);
          }
        }
        const Vec3 bgr = sum / (n * n);
        if (options.grey) {
          out.at<uint8_t>(v, u) = cv::saturate_cast<uint8_t>(0.114 * bgr[0] + 0.587 * bgr[1] + 0.299 * bgr[2]);
        } else {
          out.at<cv::Vec3b>(v, u) = cv::Vec3b(cv::saturate_cast<uint8_t>(bgr[0]), cv::saturate_cast<uint8_t>(bgr[1]),
                                              cv::saturate_cast<uint8_t>(bgr[2]));
        }
      }
    }
  });
  return out;
}

cv::Mat texture_at_view(const View& view, const Pose& T_world_view, cv::Mat* on_surface) {
  cv::Mat out(view.height(), view.width(), CV_8UC3, cv::Scalar::all(0));
  cv::Mat valid(view.height(), view.width(), CV_8UC1, cv::Scalar(0));
  cv::parallel_for_(cv::Range(0, view.height()), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      for (int u = 0; u < view.width(); ++u) {
        Vec3 p;
        if (!view.pixel_to_point(u, v, p)) continue;
        const Vec3 bgr = Scene::texture(T_world_view * p);
        out.at<cv::Vec3b>(v, u) = cv::Vec3b(cv::saturate_cast<uint8_t>(bgr[0]), cv::saturate_cast<uint8_t>(bgr[1]),
                                            cv::saturate_cast<uint8_t>(bgr[2]));
        valid.at<uint8_t>(v, u) = 255;
      }
    }
  });
  if (on_surface) *on_surface = valid;
  return out;
}

}  // namespace omniview::synthetic

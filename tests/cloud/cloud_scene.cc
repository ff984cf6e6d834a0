#include "cloud_scene.h"

#include "core/synthetic/render.h"
#include "core/synthetic/spot_like_rig.h"

namespace omniview::test {

synthetic::Scene textured_room() {
  synthetic::Scene scene;
  scene.add(synthetic::Box{Vec3(-4.5, -3.5, 0), Vec3(4.5, 3.5, 3)});
  return scene;
}

Pose T_body_lidar() { return make_pose(Vec3(-0.1, 0, 0.3), 0, 0, 0); }

std::shared_ptr<Rig> rig_in_world(const Pose& T_world_body) {
  auto rig = std::make_shared<Rig>(synthetic::spot_like_rig());
  rig->add_frame("lidar", "body", T_body_lidar());
  rig->add_frame("world", "body", T_world_body.inverse());
  return rig;
}

std::vector<cv::Mat> render_images(const synthetic::Scene& scene, const Rig& rig, bool grey) {
  std::vector<cv::Mat> images;
  synthetic::RenderOptions options;
  options.supersample = 1;
  options.grey = grey;
  for (size_t i = 0; i < rig.cameras().size(); ++i) images.push_back(synthetic::render_camera(scene, rig, i, "world", options));
  return images;
}

Visibility::Visibility(const synthetic::Scene& scene, const Rig& rig) : scene_(scene), rig_(rig) {
  for (size_t i = 0; i < rig.cameras().size(); ++i) {
    const Pose T_world_cam = rig.camera_pose("world", i);
    T_cam_world_.push_back(T_world_cam.inverse());
    centre_world_.push_back(T_world_cam.translation());
  }
}

bool Visibility::camera_sees(size_t camera, const Vec3& p_world) const {
  const Camera& cam = rig_.cameras()[camera];
  const Vec3 p_cam = T_cam_world_[camera] * p_world;
  Vec2 uv;
  if (!project(cam.model, p_cam, uv) || !cam.in_image(uv.x(), uv.y())) return false;
  const Vec3 dir = p_world - centre_world_[camera];
  const auto hit = scene_.intersect(centre_world_[camera], dir);
  return hit && hit->t > 1 - 1e-3;  // dir spans the whole way: t = 1 at the point
}

bool Visibility::any_camera_sees(const Vec3& p_world) const {
  for (size_t c = 0; c < rig_.cameras().size(); ++c) {
    if (camera_sees(c, p_world)) return true;
  }
  return false;
}

}  // namespace omniview::test

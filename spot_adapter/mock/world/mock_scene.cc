#include "spot_adapter/mock/world/mock_scene.h"

#include "core/synthetic/spot_like_rig.h"

namespace omniview::spot_mock {

std::optional<SceneKind> parse_scene_kind(std::string_view name) {
  if (name == "room") return SceneKind::kRoom;
  if (name == "test") return SceneKind::kTest;
  return std::nullopt;
}

const char* to_string(SceneKind kind) { return kind == SceneKind::kRoom ? "room" : "test"; }

synthetic::Scene make_scene(SceneKind kind) {
  using synthetic::Plane;
  if (kind == SceneKind::kRoom) return synthetic::Scene::room();  // 8 x 5.5 x 3 m around the origin
  synthetic::Scene s;
  s.add(Plane{Vec3::UnitZ(), 0.0});
  // Only above the floor, so no camera sees the wall's mirror image below the ground.
  Plane wall{Vec3::UnitX(), kTestWallX};
  wall.lo.z() = 0;
  s.add(wall);
  return s;
}

const std::vector<MockCamera>& mock_cameras() {
  static const std::vector<MockCamera> cameras = {
      {"frontleft_fisheye_image", "frontleft", "frontleft_fisheye"},
      {"frontright_fisheye_image", "frontright", "frontright_fisheye"},
      {"left_fisheye_image", "left", "left_fisheye"},
      {"right_fisheye_image", "right", "right_fisheye"},
      {"back_fisheye_image", "back", "back_fisheye"},
  };
  return cameras;
}

namespace {

Pose T_body_vision() { return Pose(Eigen::Translation3d(0, 0, -kBodyHeightM)); }

}  // namespace

Rig mock_rig() {
  Rig rig = synthetic::spot_like_rig();
  rig.add_frame(kWorldFrame, kBodyFrame, T_body_vision());
  return rig;
}

Pose T_body_lidar() { return Pose(Eigen::Translation3d(-0.1, 0, 0.2)); }  // on top of the body

std::vector<FrameEdge> mock_frame_tree() {
  // The robot stands level at the world origin, so the world frames differ from body only
  // by its height; odom and vision coincide as after start-up.
  std::vector<FrameEdge> edges = {
      {kBodyFrame, "", Pose::Identity()},
      {kWorldFrame, kBodyFrame, T_body_vision()},
      {"odom", kBodyFrame, T_body_vision()},
      {"gpe", kBodyFrame, T_body_vision()},
      {"flat_body", kBodyFrame, Pose::Identity()},
      {kLidarFrame, kBodyFrame, T_body_lidar()},
  };
  // Spot's chain body -> mount -> sensor: the sensor frame is the mount turned into the
  // optical convention, so clients must compose the two.
  const Rig rig = synthetic::spot_like_rig();
  for (size_t i = 0; i < mock_cameras().size(); ++i) {
    const MockCamera& cam = mock_cameras()[i];
    const Pose T_body_sensor = rig.camera_pose(kBodyFrame, i);
    Pose T_body_mount = T_body_sensor;
    T_body_mount.linear() = T_body_sensor.linear() * R_view_optical().transpose();
    Pose T_mount_sensor = Pose::Identity();
    T_mount_sensor.linear() = R_view_optical();
    edges.push_back({cam.mount_frame, kBodyFrame, T_body_mount});
    edges.push_back({cam.sensor_frame, cam.mount_frame, T_mount_sensor});
  }
  return edges;
}

const std::vector<std::string>& joint_names() {
  static const std::vector<std::string> names = {"fl.hx", "fl.hy", "fl.kn", "fr.hx", "fr.hy", "fr.kn",
                                                 "hl.hx", "hl.hy", "hl.kn", "hr.hx", "hr.hy", "hr.kn"};
  return names;
}

double standing_angle(const std::string& joint) {
  if (joint.ends_with(".hy")) return 0.8;
  if (joint.ends_with(".kn")) return -1.6;
  return 0.0;
}

}  // namespace omniview::spot_mock

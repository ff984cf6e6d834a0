#include "spot_adapter/source/spot_rig.h"

#include <cmath>
#include <set>

#include "spot_adapter/client/spot_error.h"

namespace omniview::spot {
namespace {

// Where the vertical through body's origin meets the ground plane (z = 0 of `gpe`, the
// robot's ground plane estimate); oriented like flat_body (body without roll and pitch).
void add_footprint(Rig& rig) {
  const auto& frames = rig.frames();
  const auto T_body_gpe = frames.try_lookup(kBodyFrame, "gpe");
  if (!T_body_gpe) return;  // no ground estimate: no footprint (views say which frames exist)
  const auto T_body_flat = frames.try_lookup(kBodyFrame, "flat_body");
  const Mat3 R = T_body_flat ? T_body_flat->linear() : T_body_gpe->linear();
  const Vec3 up = R.col(2);
  const Vec3 normal = T_body_gpe->linear().col(2);
  const double along = up.dot(normal);
  if (std::abs(along) < 0.5) return;  // ground steeper than 60 deg: no sensible footprint
  Pose T_body_footprint = Pose::Identity();
  T_body_footprint.linear() = R;
  T_body_footprint.translation() = up * (T_body_gpe->translation().dot(normal) / along);
  rig.add_frame(kFootprintFrame, kBodyFrame, T_body_footprint);
}

}  // namespace

std::shared_ptr<const Rig> placeholder_rig() {
  auto rig = std::make_shared<Rig>(kBodyFrame);
  for (const char* frame : {"flat_body", "gpe", "vision", "odom", kFootprintFrame}) {
    rig->add_frame(frame, kBodyFrame, Pose::Identity());
  }
  return rig;
}

std::shared_ptr<const Rig> build_spot_rig(const std::vector<Camera>& cameras,
                                          const std::map<std::string, FrameEdge>& tree) {
  auto rig = std::make_shared<Rig>(kBodyFrame);
  std::set<std::string> camera_frames;
  for (const Camera& c : cameras) camera_frames.insert(c.name);
  try {
    for (const auto& [child, edge] : tree) {
      if (!camera_frames.count(child) && child != kFootprintFrame) rig->add_frame(child, edge.parent, edge.T_parent_child);
    }
    for (Camera c : cameras) {
      const auto it = tree.find(c.name);
      if (it == tree.end()) {
        throw SpotError(SpotError::Kind::kProtocol,
                        "camera frame '" + c.name + "' is not in the robot's frame tree, so its pose is unknown");
      }
      c.parent_frame = it->second.parent;
      c.T_parent_cam = it->second.T_parent_child;
      rig->add_camera(std::move(c));
    }
    for (const Camera& c : cameras) {
      if (!rig->frames().try_lookup(kBodyFrame, c.name)) {
        throw SpotError(SpotError::Kind::kProtocol,
                        "the robot's frame tree does not connect camera frame '" + c.name + "' to 'body'");
      }
    }
    add_footprint(*rig);
  } catch (const std::invalid_argument& e) {  // a cycle, a frame twice
    throw SpotError(SpotError::Kind::kProtocol, std::string("the robot's frame tree is not a tree: ") + e.what());
  }
  return rig;
}

bool edge_moved(const FrameEdge& a, const FrameEdge& b) {
  if (a.parent != b.parent) return true;
  const double shift = (a.T_parent_child.translation() - b.T_parent_child.translation()).norm();
  const Eigen::AngleAxisd turn(a.T_parent_child.linear().transpose() * b.T_parent_child.linear());
  return shift > 1e-3 || std::abs(turn.angle()) > 0.05 * M_PI / 180;
}

}  // namespace omniview::spot

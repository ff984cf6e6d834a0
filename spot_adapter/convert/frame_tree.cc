#include "spot_adapter/convert/frame_tree.h"

#include <algorithm>
#include <cmath>

#include "spot_adapter/client/spot_error.h"

namespace omniview::spot {

Pose to_pose(const bosdyn::api::SE3Pose& pose, const std::string& what) {
  const Vec3 t(pose.position().x(), pose.position().y(), pose.position().z());
  const auto& r = pose.rotation();
  Eigen::Quaterniond q(r.w(), r.x(), r.y(), r.z());
  const double norm = q.norm();
  if (!t.allFinite() || !std::isfinite(norm)) {
    throw SpotError(SpotError::Kind::kProtocol, what + ": the pose holds numbers that are not finite");
  }
  if (std::abs(norm - 1) > 1e-3) {
    throw SpotError(SpotError::Kind::kProtocol,
                    what + ": the rotation is not a unit quaternion (norm " + std::to_string(norm) + ")");
  }
  Pose p = Pose::Identity();
  p.linear() = q.normalized().toRotationMatrix();
  p.translation() = t;
  return p;
}

std::vector<FrameEdge> frame_edges(const bosdyn::api::FrameTreeSnapshot& snapshot, const std::string& what) {
  std::vector<FrameEdge> edges;
  for (const auto& [child, edge] : snapshot.child_to_parent_edge_map()) {
    if (edge.parent_frame_name().empty()) continue;  // a root
    if (child.empty()) throw SpotError(SpotError::Kind::kProtocol, what + ": a frame with an empty name");
    edges.push_back({child, edge.parent_frame_name(),
                     to_pose(edge.parent_tform_child(), what + ": frame '" + child + "'")});
  }
  // Protobuf maps iterate in no particular order; rigs built from the same tree must match.
  std::sort(edges.begin(), edges.end(), [](const FrameEdge& a, const FrameEdge& b) { return a.child < b.child; });
  return edges;
}

}  // namespace omniview::spot

#include "core/cloud/self_filter.h"

#include <limits>

namespace omniview {

SelfFilter::SelfFilter(const robot::RobotModel& model, double margin_m) : model_(model), margin_(margin_m) {
  const Eigen::Vector3f m = Eigen::Vector3f::Constant(static_cast<float>(margin_m));
  for (const auto& visual : model.visuals()) {
    if (visual.mesh.positions.empty()) continue;
    Box b{visual.link, Eigen::Vector3f::Constant(std::numeric_limits<float>::max()),
          Eigen::Vector3f::Constant(std::numeric_limits<float>::lowest())};
    for (const auto& p : visual.mesh.positions) {
      b.lo = b.lo.cwiseMin(p);
      b.hi = b.hi.cwiseMax(p);
    }
    b.lo -= m;
    b.hi += m;
    boxes_.push_back(b);
  }
}

size_t SelfFilter::mark(PointCloud& cloud, const std::vector<double>& positions, const Pose& T_root_cloud) const {
  cloud.check("cloud");
  if (cloud.flags.empty()) cloud.flags.assign(cloud.size(), 0);
  if (boxes_.empty()) return 0;
  const auto link_poses = model_.link_poses(positions);
  // Each box's transform from the cloud frame, and the whole body's bounds in the cloud
  // frame, so that the many points far from the robot cost one test.
  struct Posed {
    Eigen::Matrix<float, 3, 4> T_box_cloud;
    Eigen::Vector3f lo, hi;
  };
  std::vector<Posed> posed;
  Eigen::Vector3f all_lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  Eigen::Vector3f all_hi = Eigen::Vector3f::Constant(std::numeric_limits<float>::lowest());
  const Pose T_cloud_root = T_root_cloud.inverse();
  for (const auto& b : boxes_) {
    const Pose T_cloud_link = T_cloud_root * link_poses[b.link];
    posed.push_back({(T_cloud_link.inverse()).matrix().topRows<3>().cast<float>(), b.lo, b.hi});
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector3d corner((k & 1 ? b.hi : b.lo).x(), (k & 2 ? b.hi : b.lo).y(), (k & 4 ? b.hi : b.lo).z());
      const Eigen::Vector3f c = (T_cloud_link * corner).cast<float>();
      all_lo = all_lo.cwiseMin(c);
      all_hi = all_hi.cwiseMax(c);
    }
  }
  size_t marked = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3f& p = cloud.points[i];
    if (!((p.array() >= all_lo.array()).all() && (p.array() <= all_hi.array()).all())) continue;
    for (const auto& b : posed) {
      const Eigen::Vector3f q = b.T_box_cloud * p.homogeneous();
      if ((q.array() >= b.lo.array()).all() && (q.array() <= b.hi.array()).all()) {
        cloud.flags[i] |= cloud_flags::kSelf;
        ++marked;
        break;
      }
    }
  }
  return marked;
}

}  // namespace omniview

#include "server/web/foxglove/foxglove_fields.h"

namespace omniview::foxglove_fields {

void set_pinhole(foxglove::CameraCalibration& c, double fx, double fy, double cx, double cy) {
  for (double v : {fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0}) c.add_k(v);
  for (double v : {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0}) c.add_r(v);
  for (double v : {fx, 0.0, cx, 0.0, 0.0, fy, cy, 0.0, 0.0, 0.0, 1.0, 0.0}) c.add_p(v);
}

void add_transform(foxglove::FrameTransforms& out, const google::protobuf::Timestamp& stamp, const std::string& parent,
                   const std::string& child, const Eigen::Vector3d& t, const Eigen::Quaterniond& q) {
  auto* tf = out.add_transforms();
  *tf->mutable_timestamp() = stamp;
  tf->set_parent_frame_id(parent);
  tf->set_child_frame_id(child);
  tf->mutable_translation()->set_x(t.x());
  tf->mutable_translation()->set_y(t.y());
  tf->mutable_translation()->set_z(t.z());
  tf->mutable_rotation()->set_x(q.x());
  tf->mutable_rotation()->set_y(q.y());
  tf->mutable_rotation()->set_z(q.z());
  tf->mutable_rotation()->set_w(q.w());
}

}  // namespace omniview::foxglove_fields

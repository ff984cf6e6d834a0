#include "spot_adapter/mock/wire/spot_messages.h"

#include <atomic>

#include "spot_adapter/mock/world/mock_scene.h"

namespace omniview::spot_mock {
namespace {
std::atomic<int64_t> robot_clock_offset_ms{0};
}  // namespace

void set_robot_clock_offset(std::chrono::milliseconds offset) { robot_clock_offset_ms = offset.count(); }

std::chrono::system_clock::time_point robot_now() {
  return std::chrono::system_clock::now() + std::chrono::milliseconds(robot_clock_offset_ms.load());
}

google::protobuf::Timestamp to_timestamp(std::chrono::system_clock::time_point t) {
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
  google::protobuf::Timestamp out;
  out.set_seconds(ns / 1000000000);
  out.set_nanos(static_cast<int>(ns % 1000000000));
  return out;
}

void fill_response_header(const bosdyn::api::RequestHeader& request, const google::protobuf::Timestamp& received,
                          bosdyn::api::ResponseHeader* response) {
  *response->mutable_request_header() = request;
  *response->mutable_request_received_timestamp() = received;
  *response->mutable_response_timestamp() = now_timestamp();
  response->mutable_error()->set_code(bosdyn::api::CommonError::CODE_OK);
}

void set_header_error(bosdyn::api::ResponseHeader* header, bosdyn::api::CommonError::Code code,
                      const std::string& message) {
  header->mutable_error()->set_code(code);
  header->mutable_error()->set_message(message);
}

bosdyn::api::SE3Pose to_se3_pose(const Pose& pose) {
  bosdyn::api::SE3Pose out;
  const Vec3 t = pose.translation();
  out.mutable_position()->set_x(t.x());
  out.mutable_position()->set_y(t.y());
  out.mutable_position()->set_z(t.z());
  const Eigen::Quaterniond q(pose.linear());
  out.mutable_rotation()->set_x(q.x());
  out.mutable_rotation()->set_y(q.y());
  out.mutable_rotation()->set_z(q.z());
  out.mutable_rotation()->set_w(q.w());
  return out;
}

const bosdyn::api::FrameTreeSnapshot& mock_frame_tree_snapshot() {
  static const bosdyn::api::FrameTreeSnapshot snapshot = [] {
    bosdyn::api::FrameTreeSnapshot s;
    for (const FrameEdge& edge : mock_frame_tree()) {
      auto& parent_edge = (*s.mutable_child_to_parent_edge_map())[edge.child];
      parent_edge.set_parent_frame_name(edge.parent);
      *parent_edge.mutable_parent_tform_child() = to_se3_pose(edge.T_parent_child);
    }
    return s;
  }();
  return snapshot;
}

}  // namespace omniview::spot_mock

// Pieces every spot-mock answer shares, in bosdyn.api terms: the response header (BD
// clients reject one without CODE_OK and the echoed request header), timestamps, poses and
// the frame tree.
#pragma once

#include <chrono>
#include <string>

#include <google/protobuf/timestamp.pb.h>

#include "bosdyn/api/geometry.pb.h"
#include "bosdyn/api/header.pb.h"
#include "core/geometry/pose.h"

namespace omniview::spot_mock {

google::protobuf::Timestamp to_timestamp(std::chrono::system_clock::time_point t);

// The robot's clock: this machine's plus an offset (--clock-offset-ms), as a real robot's
// clock differs from its clients'. Every time the mock sends is on it.
void set_robot_clock_offset(std::chrono::milliseconds offset);
std::chrono::system_clock::time_point robot_now();
inline google::protobuf::Timestamp now_timestamp() { return to_timestamp(robot_now()); }

// request_header copied, received/response times set, error.code = CODE_OK.
void fill_response_header(const bosdyn::api::RequestHeader& request, const google::protobuf::Timestamp& received,
                          bosdyn::api::ResponseHeader* response);

// Marks an answer as failed the way the robot's services do: in the header, the gRPC status OK.
void set_header_error(bosdyn::api::ResponseHeader* header, bosdyn::api::CommonError::Code code,
                      const std::string& message);

bosdyn::api::SE3Pose to_se3_pose(const Pose& pose);

// mock_frame_tree() as Spot sends it (key = child; the root has an empty parent).
const bosdyn::api::FrameTreeSnapshot& mock_frame_tree_snapshot();

}  // namespace omniview::spot_mock

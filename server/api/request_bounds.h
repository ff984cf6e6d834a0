// Bounds on every field of every request a client sends, checked before the request is
// used (after authentication: a stranger learns nothing from them). Strings are short and
// printable, numbers finite, lists short. What the fields mean is checked further in
// (validate(ViewSpec) for CreateView and UpdateView, the URDF's limits for joints); this
// is the floor under all of it, so a message can always quote what was sent.
#pragma once

#include <cstddef>

#include <google/protobuf/message.h>
#include <grpcpp/support/status.h>

namespace omniview {

constexpr size_t kMaxRequestText = 256;    // any string field: names of views, sources, frames, joints
constexpr int kMaxRequestListEntries = 256;  // any repeated or map field (joint positions)

// Cloud requests (StreamClouds, GetCloud): a voxel finer than 1 cm would cost more than
// the cloud it thins; a crop box is in metres around the robot; GetCloud waits at most a minute.
constexpr double kMinCloudVoxelM = 0.01;
constexpr double kMaxCloudVoxelM = 10;
constexpr double kMaxCloudCropM = 10000;
constexpr int kMaxCloudWaitMs = 60000;

// OK, or INVALID_ARGUMENT naming the field ("spec.name", "positions[elbow]") and quoting
// at most a short prefix of its value.
// Cloud requests are also checked for what their options mean (voxel size, crop box, rate,
// wait), through check_cloud_request.
grpc::Status check_request_bounds(const google::protobuf::Message& request);
grpc::Status check_cloud_request(const google::protobuf::Message& request);

}  // namespace omniview

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

// OK, or INVALID_ARGUMENT naming the field ("spec.name", "positions[elbow]") and quoting
// at most a short prefix of its value.
grpc::Status check_request_bounds(const google::protobuf::Message& request);

}  // namespace omniview

// Between the core's types and the omniview.v1 messages. Shared by the service, the
// pipeline (frame descriptions) and the CLI, so the API means the same everywhere.
#pragma once

#include <string>

#include "core/rig/rig.h"
#include "core/view/view.h"
#include "core/view/view_spec.h"
#include "omniview/v1/omniview.pb.h"

namespace omniview {

v1::Vec3 to_proto(const Vec3& v);
Vec3 from_proto(const v1::Vec3& v);
v1::Transform to_proto(const Pose& pose);
Pose from_proto(const v1::Transform& t);

v1::ViewType to_proto(ViewType type);
v1::Fusion to_proto(Fusion fusion);
v1::Depth to_proto(Depth depth);
// Throw std::invalid_argument naming `what` for UNSPECIFIED or unknown values.
ViewType from_proto(v1::ViewType type, const std::string& what);
Fusion from_proto(v1::Fusion fusion, const std::string& what);
Depth from_proto(v1::Depth depth, const std::string& what);

// Every field set.
v1::ViewSpec to_proto(const ViewSpec& spec);

// A new view from a request: the type's defaults (default_view_spec), then every field the
// request sets. Does not validate. Throws std::invalid_argument if the type is missing.
ViewSpec spec_from_proto(const v1::ViewSpec& request);
// Sets the fields `patch` sets, leaving the rest. Changing the type resets nothing else.
void apply_patch(const v1::ViewSpec& patch, ViewSpec& spec);
// Pan/tilt/roll steps and zoom (see omniview.proto, ViewDelta). Throws
// std::invalid_argument for a zoom <= 0 or on a view type without a zoom.
void apply_delta(const v1::ViewDelta& delta, ViewSpec& spec);

// Zoom as a focal-length factor relative to a 90 deg hfov: zoom 1 = 90 deg, 2 = 53.1 deg.
double hfov_from_zoom(double zoom);
double zoom_from_hfov(double hfov_deg);

// [fx, fy, cx, cy] for perspective and bird's-eye views; empty for the others.
std::vector<double> pinhole_intrinsics(const View& view);

v1::Camera to_proto(const Camera& camera, const Rig& rig, const std::string& source);

}  // namespace omniview

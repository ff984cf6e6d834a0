// Parts of Foxglove's messages that the WebSocket endpoint and the MCAP export fill alike:
// a pinhole CameraCalibration's matrices and one FrameTransform.
#pragma once

#include <string>

#include <Eigen/Geometry>

#include "foxglove/omniview_schemas.pb.h"

namespace omniview::foxglove_fields {

// K, R (identity) and P of an undistorted pinhole (fx, fy, cx, cy in pixels).
void set_pinhole(foxglove::CameraCalibration& c, double fx, double fy, double cx, double cy);

// One transform: `child`'s pose (translation t, rotation q) in `parent`.
void add_transform(foxglove::FrameTransforms& out, const google::protobuf::Timestamp& stamp, const std::string& parent,
                   const std::string& child, const Eigen::Vector3d& t, const Eigen::Quaterniond& q);

}  // namespace omniview::foxglove_fields

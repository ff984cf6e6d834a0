// omniview's core types (cameras, rigs, clouds, joints) as the Foxglove messages an MCAP
// export writes, serialized. The live endpoint (server/web/foxglove) builds the same
// messages from the API's types; both use the schemas of server/web/foxglove/proto.
#pragma once

#include <chrono>
#include <map>
#include <string>

#include "core/cloud/point_cloud.h"
#include "core/rig/rig.h"
#include "core/view/view.h"

namespace omniview::export_mcap {

uint64_t to_ns(std::chrono::system_clock::time_point t);

// A camera's calibration as foxglove.CameraCalibration: pinhole with radtan (or none) as
// "plumb_bob", pinhole with equidistant as "kannala_brandt". Empty for the models Foxglove
// has no name for (omni, ds, eucm, fov): their images are still exported.
std::string camera_calibration(const Camera& camera, uint64_t time_ns);
// A view's virtual pinhole (no distortion); empty for the panoramas and fisheye views.
std::string view_calibration(const View& view, const std::string& frame_id, uint64_t time_ns);

// An encoded image (jpeg or png) or an H.264 access unit.
std::string compressed_image(const std::string& frame_id, uint64_t time_ns, const std::string& format,
                             std::string_view data);
std::string compressed_video(const std::string& frame_id, uint64_t time_ns, std::string_view data);

// The view frame and its optical frame ("view/NAME", "view/NAME/optical"), the names the
// Foxglove endpoint gives them.
std::string view_frame(const std::string& view);
std::string view_optical_frame(const std::string& view);

// Every frame of the rig under its parent, and each view's frame (posed in the rig's
// default frame) with its optical frame under it, as one foxglove.FrameTransforms.
struct PosedView {
  std::string name;
  Pose T_robot_view;
};
std::string frame_transforms(const Rig& rig, const std::vector<PosedView>& views, uint64_t time_ns);

// A cloud as foxglove.PointCloud: x, y, z (float32), then red, green, blue, alpha (uint8,
// alpha 255; if the cloud has colours) and intensity (float32, if it has them). Non-finite
// points are left out.
std::string point_cloud(const PointCloud& cloud, uint64_t time_ns);

// omniview.JointStates (server/web/foxglove/proto/omniview/joint_states.proto).
std::string joint_states(const std::map<std::string, double>& joints, uint64_t time_ns);

}  // namespace omniview::export_mcap

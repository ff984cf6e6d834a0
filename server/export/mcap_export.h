// A recording (server/recording) as one MCAP file for Foxglove and Lichtblick: what
// `omniview export` writes. Per frame set of the recording, stamped with its capture time
// (log time = publish time = the message's own timestamp, ns since the Unix epoch):
//
//   /cameras/NAME/image        foxglove.CompressedImage  the recorded bytes (jpeg or png)
//   /cameras/NAME/calibration  foxglove.CameraCalibration (pinhole models: plumb_bob,
//                              kannala_brandt; none for omni, ds, eucm, fov)
//   /views/NAME                foxglove.CompressedVideo (h264: Annex B, one access unit a
//                              message, SPS/PPS with each key frame, one a second; no
//                              B-frames) or foxglove.CompressedImage (jpeg): the view
//                              rendered again from the recorded images as the daemon does
//                              (its map, fusion and gain compensation; no robot overlay)
//   /views/NAME/calibration    foxglove.CameraCalibration (perspective views)
//   /tf                        foxglove.FrameTransforms: the rig's frames and each view's
//                              frame and optical frame (view/NAME, view/NAME/optical); on
//                              the first frame set, on a rig change and once a second
//   /cloud                     foxglove.PointCloud: each recorded lidar cloud, coloured
//                              from the frame set's images (core/cloud's colourer)
//   /joint_states              omniview.JointStates (names, positions), where recorded
//
// Schemas: protobuf FileDescriptorSets (server/web/foxglove/foxglove_schema.h).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/view/view_spec.h"
#include "server/recording/recording.h"

namespace omniview::export_mcap {

enum class ViewEncoding { kH264, kJpeg };

struct ExportOptions {
  std::vector<ViewSpec> views;           // rendered views (none: cameras, clouds, tf, joints only)
  ViewEncoding encoding = ViewEncoding::kH264;
  int quality = 50;                      // 1..100: JPEG quality, or H.264 as the streams' (CRF 51 - q/2)
  bool cameras = true;                   // the recorded camera images and calibrations
  bool clouds = true;                    // the recorded clouds
  bool colour_clouds = true;             // ... coloured from the images
  size_t chunk_bytes = 1 << 20;
  // Called after each frame set (done, total).
  std::function<void(size_t, size_t)> progress;
};

struct ExportSummary {
  size_t frame_sets = 0;
  std::map<std::string, uint64_t> messages;  // per topic
  uint64_t bytes = 0;
  uint64_t start_ns = 0, end_ns = 0;
  std::vector<std::string> notes;  // what was left out, and why
};

// Writes `path`. Throws std::invalid_argument naming the view for a view the recording's
// rig cannot render (unknown frame, odd size for H.264), std::runtime_error naming the file
// for an unreadable image or cloud of the recording or a failed write; the half-written
// output is removed then.
ExportSummary export_recording(const Recording& recording, const std::string& path, const ExportOptions& options);

}  // namespace omniview::export_mcap

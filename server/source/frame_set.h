// One synchronised set of camera images, as a source delivers it to the pipeline.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "core/cloud/point_cloud.h"
#include "core/cloud/trajectory.h"
#include "core/rig/rig.h"

namespace omniview {

// The bytes a source received for one image, when it received encoded data (a robot's
// JPEG): recording keeps them as they are instead of re-encoding.
struct EncodedImage {
  std::string format;          // "jpeg" or "png"; empty: none kept
  std::shared_ptr<const std::vector<uint8_t>> bytes;
};

struct FrameSet {
  uint64_t sequence = 0;  // per source, increasing
  std::chrono::system_clock::time_point capture_time;  // of the images (robot clock if known)
  std::chrono::steady_clock::time_point arrival;       // when the daemon had them: latency starts here
  // The rig the images belong to, and its version: a change (new extrinsics, say) makes
  // the pipeline rebuild the maps of the views that use it.
  std::shared_ptr<const Rig> rig;
  uint64_t rig_version = 0;
  // One per rig camera, in rig order; CV_8UC1 or CV_8UC3 (BGR). An empty Mat: the camera
  // was not pulled this cycle (no active view needs it).
  std::vector<cv::Mat> images;
  std::vector<EncodedImage> encoded;  // empty, or one per image
  // The robot's joint positions (name -> rad, or m for prismatic joints) as of these
  // images, for the robot overlay; null when the source does not report them.
  std::shared_ptr<const std::map<std::string, double>> joints;
  // A lidar cloud taken with these images (its own frame and stamp), for coloured clouds;
  // null when the source has none this cycle or nobody wants clouds (Source::set_cloud_wanted).
  std::shared_ptr<const PointCloud> cloud;
  // Depth images as points, one cloud per depth camera in its own frame, while a depth view
  // is watched (Source::set_depth_wanted); empty otherwise.
  std::vector<std::shared_ptr<const PointCloud>> depth;
  // The robot's recent motion: the rig's default frame in a fixed frame (odometry) over the
  // last moments, up to these images, so a cloud can be coloured from images taken while the
  // robot moved (time sync). Null when the source knows none: the robot is assumed still.
  std::shared_ptr<const Trajectory> motion;
};

}  // namespace omniview

// A coloured cloud made into what one client asked for: moved into its output frame, cut
// to its crop box, thinned to one point per voxel, and packed into the API's binary point
// layout (v1::PointCloud: a field list, a stride and little-endian bytes).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "core/cloud/point_cloud.h"
#include "core/geometry/pose.h"
#include "omniview/v1/omniview.pb.h"

namespace omniview {

struct CloudShape {
  std::string frame;                      // the output frame's name
  Pose T_out_cloud = Pose::Identity();    // the cloud's frame in the output frame
  double voxel_m = 0;                     // 0: keep every point
  std::optional<Eigen::AlignedBox3d> crop;  // in the output frame
};

// The finite points of `coloured` (rgb, flags and camera present, as the colourer leaves
// them) in the output frame, inside the crop box, one per voxel: a voxel's point is the
// mean of its points, its colour the mean of its coloured points' colours, its flags
// kColoured when any point was coloured (else kSelf, else kOccluded, as any had them).
PointCloud shape_cloud(const PointCloud& coloured, const CloudShape& shape);

// The layout every message carries (x y z float32, r g b flags camera uint8).
inline constexpr uint32_t kPackedPointStride = 17;

// `cloud` (rgb, flags and camera present) packed, with its field list, frame, stamp and
// flag counts; the caller fills source, sequence, cameras and timings.
v1::PointCloud pack_cloud(const PointCloud& cloud);

}  // namespace omniview

// What one client asked of a source's clouds (StreamClouds, GetCloud): how to colour them,
// which frame to send them in, and how to thin and cut them.
#pragma once

#include <optional>
#include <string>

#include <Eigen/Geometry>

#include "core/cloud/colourer.h"
#include "omniview/v1/omniview.pb.h"

namespace omniview {

struct CloudRequest {
  std::string frame;  // output frame; empty: the rig's default frame
  double voxel_m = 0;  // 0: every point
  std::optional<Eigen::AlignedBox3d> crop;  // in the output frame
  Fusion fusion = Fusion::kNearestCentre;
  bool occlusion = true;

  // Clients asking the same colouring share one colouring pass per cloud.
  bool same_colouring(const CloudRequest& o) const { return fusion == o.fusion && occlusion == o.occlusion; }
  // Clients asking the same shape (frame, voxel, crop) of the same colouring share one
  // message per cloud, as frames are encoded once per encoding.
  bool same_shape(const CloudRequest& o) const {
    const bool same_crop = crop.has_value() == o.crop.has_value() &&
                           (!crop || (crop->min() == o.crop->min() && crop->max() == o.crop->max()));
    return same_colouring(o) && frame == o.frame && voxel_m == o.voxel_m && same_crop;
  }
  ColourOptions colour_options() const;
};

// The request's options as they came over the wire (bounds already checked:
// request_bounds.h). Throws std::invalid_argument naming the field for an unknown fusion.
CloudRequest cloud_request_from_proto(const v1::CloudOptions& options);

}  // namespace omniview

// A cloud message from omniviewd (v1::PointCloud) as core's PointCloud, decoded by the
// message's own field list (name, offset, datatype, count), never by an assumed layout.
#pragma once

#include "core/cloud/point_cloud.h"
#include "omniview/v1/omniview.pb.h"

namespace omniview::cli {

// x, y, z are required; r, g, b, flags and camera are taken when present; other fields are
// skipped. Throws std::runtime_error naming the field for a layout that does not fit the
// data (an offset past the stride, a data size other than point_count * point_stride).
PointCloud cloud_from_message(const v1::PointCloud& message);

}  // namespace omniview::cli

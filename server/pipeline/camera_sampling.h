// How coarsely a view's map samples each camera, for Source::set_camera_sampling: a source
// that can decode smaller images (DCT scaling) uses it when every view needs less.
#pragma once

#include <vector>

#include "core/map/fusion_map.h"

namespace omniview {

// Per rig camera: the distance between horizontally or vertically neighbouring view
// samples in that camera's image, as a fraction of its width, taken at the 25th
// percentile (three quarters of the view's pixels sample the camera at least this
// coarsely; the oversampled poles of a panorama do not hold the rest back). 0 for a
// camera the map does not read.
std::vector<double> camera_sampling(const FusionMap& map);

}  // namespace omniview

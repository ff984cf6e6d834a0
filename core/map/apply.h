// Applying a FusionMap: one bilinear pass over the output.
#pragma once

#include <vector>

#include <opencv2/core/mat.hpp>

#include "core/gain/camera_gains.h"
#include "core/map/fusion_map.h"

namespace omniview {

// images[i] is rig camera i's image: CV_8UC1 (greyscale) or CV_8UC3 (BGR), of the size it
// is calibrated for. Cameras the map does not use may be empty Mats. `out` becomes
// map.height x map.width with `out_channels` (1 or 3) channels; greyscale inputs feed
// colour outputs and vice versa. Pixels no camera sees are 0.
// Throws std::invalid_argument naming the camera for a missing, wrong-size or wrong-type
// image. Runs on OpenCV's thread pool.
void apply_map(const FusionMap& map, const std::vector<cv::Mat>& images, cv::Mat& out, int out_channels);

// The same with each camera's samples scaled by its gains (per output channel; see
// core/gain). Empty gains: as above. Throws std::invalid_argument if non-empty gains do not
// have one gain per camera and output channel.
void apply_map(const FusionMap& map, const std::vector<cv::Mat>& images, cv::Mat& out, int out_channels,
               const CameraGains& gains);

}  // namespace omniview

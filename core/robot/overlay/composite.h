// Alpha compositing of a robot layer over a view's image, in place.
//
// Per pixel, with a = layer alpha (0..255) and the opacity in [0, 1]:
//   w = round(a * round(opacity * 256) / 255)   (0..256)
//   out = (image * (256 - w) + layer * w + 128) >> 8
// so opacity 0 leaves the image untouched and opacity 1 over alpha 255 copies the layer
// exactly. Only the layer's bounding box is touched; integer arithmetic throughout.
// A grey image gets the layer's luma (BT.601 weights, 8-bit fixed point).
#pragma once

#include <opencv2/core.hpp>

#include "core/robot/overlay/overlay_layer.h"

namespace omniview::robot {

// image: CV_8UC1 or CV_8UC3 (BGR), the layer's size. Throws std::invalid_argument otherwise.
void composite(const OverlayLayer& layer, cv::Mat& image, double opacity);

}  // namespace omniview::robot

// A rendered robot layer, ready to be composited over a view's frames.
#pragma once

#include <opencv2/core.hpp>

namespace omniview::robot {

struct OverlayLayer {
  cv::Mat bgra;  // CV_8UC4, view-sized, not premultiplied; alpha 0 where the robot is not
  cv::Rect bbox;  // the pixels with alpha > 0; empty when the robot is out of sight
};

// The bounding box of alpha > 0 in a BGRA image.
cv::Rect alpha_bounding_box(const cv::Mat& bgra);

// Draws a `width_px` wide border of `bgr` (alpha 255) around the silhouette: on pixels
// outside it within width_px (chessboard distance) of a robot pixel. Updates layer.bbox.
void add_outline(OverlayLayer& layer, int width_px, const cv::Scalar& bgr);

}  // namespace omniview::robot

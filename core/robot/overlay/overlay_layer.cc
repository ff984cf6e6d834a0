#include "core/robot/overlay/overlay_layer.h"

#include <opencv2/imgproc.hpp>

namespace omniview::robot {

cv::Rect alpha_bounding_box(const cv::Mat& bgra) {
  CV_Assert(bgra.type() == CV_8UC4);
  int top = bgra.rows, bottom = -1, left = bgra.cols, right = -1;
  for (int v = 0; v < bgra.rows; ++v) {
    const cv::Vec4b* row = bgra.ptr<cv::Vec4b>(v);
    int first = -1, last = -1;
    for (int u = 0; u < bgra.cols; ++u) {
      if (row[u][3]) {
        if (first < 0) first = u;
        last = u;
      }
    }
    if (first < 0) continue;
    top = std::min(top, v);
    bottom = v;
    left = std::min(left, first);
    right = std::max(right, last);
  }
  if (bottom < 0) return {};
  return {left, top, right - left + 1, bottom - top + 1};
}

void add_outline(OverlayLayer& layer, int width_px, const cv::Scalar& bgr) {
  if (width_px <= 0 || layer.bbox.empty()) return;
  const cv::Rect roi = (layer.bbox + cv::Point(-width_px, -width_px) + cv::Size(2 * width_px, 2 * width_px)) &
                       cv::Rect(0, 0, layer.bgra.cols, layer.bgra.rows);
  cv::Mat alpha;
  cv::extractChannel(layer.bgra(roi), alpha, 3);
  cv::Mat grown;
  cv::dilate(alpha > 0, grown, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * width_px + 1, 2 * width_px + 1)));
  const cv::Vec4b ink(cv::saturate_cast<uint8_t>(bgr[0]), cv::saturate_cast<uint8_t>(bgr[1]),
                      cv::saturate_cast<uint8_t>(bgr[2]), 255);
  for (int v = 0; v < roi.height; ++v) {
    cv::Vec4b* row = layer.bgra.ptr<cv::Vec4b>(roi.y + v) + roi.x;
    const uint8_t* ring = grown.ptr<uint8_t>(v);
    for (int u = 0; u < roi.width; ++u) {
      if (ring[u] && row[u][3] == 0) row[u] = ink;
    }
  }
  layer.bbox = alpha_bounding_box(layer.bgra(roi)) + roi.tl();
}

}  // namespace omniview::robot

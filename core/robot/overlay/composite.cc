#include "core/robot/overlay/composite.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace omniview::robot {
namespace {

// Blend weight of a layer pixel, 0..256, by its alpha, for one opacity (in 1/256).
struct Weights {
  uint16_t of_alpha[256];
  explicit Weights(uint32_t opacity256) {
    for (uint32_t a = 0; a < 256; ++a) of_alpha[a] = static_cast<uint16_t>((a * opacity256 + 127) / 255);
  }
};

inline uint8_t blend(uint32_t under, uint32_t over, uint32_t w) {
  return static_cast<uint8_t>((under * (256 - w) + over * w + 128) >> 8);
}

// Most of a robot's bounding box is either background (w = 0) or fully covered (w = 256 at
// full opacity); both skip the arithmetic.
void composite_bgr(const cv::Mat& layer, cv::Mat& image, const cv::Rect& box, const Weights& weights) {
  for (int v = box.y; v < box.br().y; ++v) {
    const uint8_t* src = layer.ptr<uint8_t>(v) + 4 * box.x;
    uint8_t* dst = image.ptr<uint8_t>(v) + 3 * box.x;
    for (int u = 0; u < box.width; ++u, src += 4, dst += 3) {
      const uint32_t w = weights.of_alpha[src[3]];
      if (w == 0) continue;
      if (w == 256) {
        dst[0] = src[0], dst[1] = src[1], dst[2] = src[2];
        continue;
      }
      dst[0] = blend(dst[0], src[0], w);
      dst[1] = blend(dst[1], src[1], w);
      dst[2] = blend(dst[2], src[2], w);
    }
  }
}

void composite_grey(const cv::Mat& layer, cv::Mat& image, const cv::Rect& box, const Weights& weights) {
  for (int v = box.y; v < box.br().y; ++v) {
    const uint8_t* src = layer.ptr<uint8_t>(v) + 4 * box.x;
    uint8_t* dst = image.ptr<uint8_t>(v) + box.x;
    for (int u = 0; u < box.width; ++u, src += 4, ++dst) {
      const uint32_t w = weights.of_alpha[src[3]];
      if (w == 0) continue;
      const uint32_t luma = (29u * src[0] + 150u * src[1] + 77u * src[2] + 128u) >> 8;
      *dst = blend(*dst, luma, w);
    }
  }
}

}  // namespace

void composite(const OverlayLayer& layer, cv::Mat& image, double opacity) {
  if (layer.bbox.empty()) return;
  if (layer.bgra.type() != CV_8UC4 || image.size() != layer.bgra.size() ||
      (image.type() != CV_8UC1 && image.type() != CV_8UC3)) {
    throw std::invalid_argument("robot overlay: cannot composite a " + std::to_string(layer.bgra.cols) + "x" +
                                std::to_string(layer.bgra.rows) + " layer onto a " + std::to_string(image.cols) + "x" +
                                std::to_string(image.rows) + " image with " + std::to_string(image.channels()) +
                                " channels (needs the same size, 8-bit grey or BGR)");
  }
  const auto opacity256 = static_cast<uint32_t>(std::lround(std::clamp(std::isfinite(opacity) ? opacity : 0.0, 0.0, 1.0) * 256));
  if (opacity256 == 0) return;
  const cv::Rect box = layer.bbox & cv::Rect(0, 0, image.cols, image.rows);
  const Weights weights(opacity256);
  if (image.channels() == 3) {
    composite_bgr(layer.bgra, image, box, weights);
  } else {
    composite_grey(layer.bgra, image, box, weights);
  }
}

}  // namespace omniview::robot

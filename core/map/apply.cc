#include "core/map/apply.h"

#include <cstring>
#include <stdexcept>

#include <opencv2/core.hpp>

namespace omniview {
namespace {

struct Source {
  const uint8_t* data = nullptr;
  size_t stride = 0;  // bytes per row; images are continuous, so width * channels
  int channels = 0;
};

// Three 8-bit channels spread over 16-bit lanes of a uint64 (0x0000_RRRR_GGGG_BBBB), so one
// multiply interpolates all three at once (SWAR, portable to ARM64). A lane never exceeds
// 255 * 256, so lanes never carry into each other.
inline uint64_t load3(const uint8_t* p) { return uint64_t{p[0]} | (uint64_t{p[1]} << 16) | (uint64_t{p[2]} << 32); }
inline uint64_t lerp_lanes(uint64_t a, uint64_t b, uint64_t f) {  // (a (256 - f) + b f + 128) / 256
  return ((a * (256 - f) + b * f + 0x0000008000800080ULL) >> 8) & 0x000000FF00FF00FFULL;
}

inline void bilinear3(const Source& s, const MapEntry& e, uint8_t* out) {
  const uint8_t* p = s.data + size_t{e.offset} * 3;
  const uint64_t top = lerp_lanes(load3(p), load3(p + 3), e.fx);
  const uint64_t bottom = lerp_lanes(load3(p + s.stride), load3(p + s.stride + 3), e.fx);
  const uint64_t v = lerp_lanes(top, bottom, e.fy);
  out[0] = static_cast<uint8_t>(v);
  out[1] = static_cast<uint8_t>(v >> 16);
  out[2] = static_cast<uint8_t>(v >> 32);
}

inline uint8_t bilinear1(const Source& s, const MapEntry& e) {
  const uint8_t* p = s.data + e.offset;
  const uint32_t fx = e.fx, fy = e.fy;
  const uint32_t top = p[0] * (256 - fx) + p[1] * fx;
  const uint32_t bottom = p[s.stride] * (256 - fx) + p[s.stride + 1] * fx;
  return static_cast<uint8_t>((top * (256 - fy) + bottom * fy + 32768) >> 16);
}

// One pixel from any source into `out_channels` channels: the mixed grey/colour path.
inline void sample_any(const Source& s, const MapEntry& e, int out_channels, uint8_t* out) {
  if (s.channels == 3) {
    uint8_t bgr[3];
    bilinear3(s, e, bgr);
    if (out_channels == 3) {
      std::memcpy(out, bgr, 3);
    } else {  // luma with BT.601 weights in 1/256, as for JPEG
      out[0] = static_cast<uint8_t>((29 * bgr[0] + 150 * bgr[1] + 77 * bgr[2] + 128) >> 8);
    }
  } else {
    const uint8_t g = bilinear1(s, e);
    for (int c = 0; c < out_channels; ++c) out[c] = g;
  }
}

// Nearest-centre maps whose sources all have the output's channel count: the hot path.
template <int C>
void apply_row_uniform(const MapEntry* m, const Source* sources, int n, uint8_t* out) {
  for (int i = 0; i < n; ++i, out += C) {
    const MapEntry e = m[i];
    if (e.cam == kNoCamera) {
      std::memset(out, 0, C);
    } else if constexpr (C == 3) {
      bilinear3(sources[e.cam], e, out);
    } else {
      out[0] = bilinear1(sources[e.cam], e);
    }
  }
}

void apply_row_general(const FusionMap& map, size_t first, const Source* sources, int n, int oc, uint8_t* out) {
  const bool blend = !map.secondary.empty();
  for (int i = 0; i < n; ++i, out += oc) {
    const MapEntry& e = map.primary[first + i];
    if (e.cam == kNoCamera) {
      std::memset(out, 0, oc);
      continue;
    }
    sample_any(sources[e.cam], e, oc, out);
    if (!blend) continue;
    const MapEntry& e2 = map.secondary[first + i];
    const uint32_t w = map.primary_weight[first + i];
    if (e2.cam == kNoCamera || w >= 256) continue;
    uint8_t other[3];
    sample_any(sources[e2.cam], e2, oc, other);
    for (int c = 0; c < oc; ++c) out[c] = static_cast<uint8_t>((out[c] * w + other[c] * (256 - w) + 128) >> 8);
  }
}

}  // namespace

void apply_map(const FusionMap& map, const std::vector<cv::Mat>& images, cv::Mat& out, int out_channels) {
  if (out_channels != 1 && out_channels != 3) {
    throw std::invalid_argument("output must have 1 or 3 channels, not " + std::to_string(out_channels));
  }
  if (images.size() != map.camera_sizes.size()) {
    throw std::invalid_argument("expected " + std::to_string(map.camera_sizes.size()) + " images (one per camera), got " +
                                std::to_string(images.size()));
  }
  std::vector<Source> sources(images.size());
  std::vector<cv::Mat> continuous(images.size());
  bool uniform = map.secondary.empty();
  for (size_t i = 0; i < images.size(); ++i) {
    if (!map.camera_used[i]) continue;
    const cv::Mat& img = images[i];
    const std::string who = "camera '" + map.camera_names[i] + "'";
    if (img.empty()) throw std::invalid_argument(who + ": no image, but the view needs this camera");
    if (img.type() != CV_8UC1 && img.type() != CV_8UC3) {
      throw std::invalid_argument(who + ": image must be 8-bit greyscale or BGR, got " + std::to_string(img.channels()) +
                                  " channel(s) of depth " + std::to_string(img.depth()));
    }
    if (img.size() != map.camera_sizes[i]) {
      throw std::invalid_argument(who + ": image is " + std::to_string(img.cols) + "x" + std::to_string(img.rows) +
                                  " but the calibration is for " + std::to_string(map.camera_sizes[i].width) + "x" +
                                  std::to_string(map.camera_sizes[i].height));
    }
    continuous[i] = img.isContinuous() ? img : img.clone();  // map offsets assume packed rows
    sources[i] = Source{continuous[i].data, continuous[i].step[0], img.channels()};
    uniform = uniform && img.channels() == out_channels;
  }
  out.create(map.height, map.width, out_channels == 3 ? CV_8UC3 : CV_8UC1);
  const int w = map.width;
  cv::parallel_for_(cv::Range(0, map.height), [&](const cv::Range& rows) {
    for (int row = rows.start; row < rows.end; ++row) {
      const size_t first = static_cast<size_t>(row) * w;
      uint8_t* dst = out.ptr<uint8_t>(row);
      if (uniform && out_channels == 3) {
        apply_row_uniform<3>(&map.primary[first], sources.data(), w, dst);
      } else if (uniform) {
        apply_row_uniform<1>(&map.primary[first], sources.data(), w, dst);
      } else {
        apply_row_general(map, first, sources.data(), w, out_channels, dst);
      }
    }
  });
}

}  // namespace omniview

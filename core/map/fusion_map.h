// The per-pixel lookup table of one view over one rig: built once per view or rig change,
// applied to every image set.
//
// Compact on purpose (8 bytes per pixel and source): apply() is bound by memory traffic.
// Coordinates are stored as the top-left source pixel of the bilinear footprint plus an
// 8-bit fraction (1/256 px, below anything visible).
#pragma once

#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "core/rig/rig.h"
#include "core/view/view.h"

namespace omniview {

inline constexpr uint8_t kNoCamera = 255;  // so a rig may have up to 254 cameras

struct MapEntry {
  uint32_t offset = 0;     // y0 * camera_width + x0 of the bilinear footprint's top-left pixel
  uint8_t fx = 0, fy = 0;  // fractional position inside the footprint, in 1/256 px
  uint8_t cam = kNoCamera; // index into the rig's cameras; kNoCamera: black
  uint8_t reserved = 0;
};
static_assert(sizeof(MapEntry) == 8);
static_assert(std::is_trivially_copyable_v<MapEntry>);  // the builder writes it as one 64-bit word

struct FusionMap {
  int width = 0, height = 0;
  Fusion fusion = Fusion::kNearestCentre;
  // Per output pixel, row-major. `primary` is the camera the paper's rule picks (or the
  // heaviest one when blending).
  std::vector<MapEntry> primary;
  // Blend only: a second camera and the primary's weight out of 256 (256: primary alone).
  std::vector<MapEntry> secondary;
  std::vector<uint16_t> primary_weight;
  // Size of each rig camera's image, as calibrated (apply() checks inputs against it).
  std::vector<cv::Size> camera_sizes;
  std::vector<std::string> camera_names;
  std::vector<bool> camera_used;  // does any pixel read from camera i?

  bool empty() const { return primary.empty(); }
  double coverage() const;  // fraction of pixels some camera sees
};

// kAdaptive (the default) evaluates the camera models exactly on an 8-pixel grid and
// interpolates inside blocks where that is provably within 0.05 px (see adaptive_rows.cc);
// kExact evaluates every pixel. Blend maps are always exact.
enum class MapPrecision { kAdaptive, kExact };

// Builds the map for `view` over `rig`, using the view's fusion policy. Runs on OpenCV's
// thread pool (cv::setNumThreads sets its size). Throws std::invalid_argument if the
// view's frame is not connected to the cameras or the rig has more than 254 cameras.
FusionMap build_map(const Rig& rig, const View& view, MapPrecision precision = MapPrecision::kAdaptive);

}  // namespace omniview

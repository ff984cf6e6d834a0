// The per-pixel lookup table of one view over one rig: built once per view or rig change,
// applied to every image set.
//
// Compact on purpose (8 bytes per pixel and source): apply() is bound by memory traffic.
// Coordinates are stored as the top-left source pixel of the bilinear footprint plus an
// 8-bit fraction (1/256 px, below anything visible).
#pragma once

#include <cstdint>
#include <string>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/rig/camera_index.h"
#include "core/map/occlusion.h"
#include "core/map/usable_region.h"
#include "core/rig/rig.h"
#include "core/view/view.h"

namespace omniview {

// No default member initialisers on purpose: a map's storage is allocated without being
// written, so each builder thread first-touches its own rows (see UninitializedAllocator).
// Use kBlackEntry for "no camera".
struct MapEntry {
  uint32_t offset;  // y0 * camera_width + x0 of the bilinear footprint's top-left pixel
  uint8_t fx, fy;   // fractional position inside the footprint, in 1/256 px
  uint8_t cam;      // index into the rig's cameras; kNoCamera: black
  uint8_t level;    // pyramid level of the camera image that offset, fx, fy address (0: full size)
};
inline constexpr MapEntry kBlackEntry{0, 0, 0, kNoCamera, 0};
static_assert(sizeof(MapEntry) == 8);
static_assert(std::is_trivially_copyable_v<MapEntry>);  // the builder writes it as one 64-bit word

// Leaves trivially constructible elements uninitialised on resize(): zeroing 8 MB in one
// thread before a parallel builder overwrites it would cost a third of a map build.
template <typename T>
struct UninitializedAllocator : std::allocator<T> {
  template <typename U>
  struct rebind {
    using other = UninitializedAllocator<U>;
  };
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    if constexpr (sizeof...(Args) == 0) {
      ::new (static_cast<void*>(p)) U;
    } else {
      ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
  }
};
using MapEntries = std::vector<MapEntry, UninitializedAllocator<MapEntry>>;

struct FusionMap {
  int width = 0, height = 0;
  Fusion fusion = Fusion::kNearestCentre;
  // Per output pixel, row-major. `primary` is the camera the paper's rule picks (or the
  // heaviest one when blending).
  MapEntries primary;
  // Blend only: a second camera and the primary's weight out of 256 (256: primary alone).
  // The second camera is kept wherever it sees the pixel, also where the seam gives it no
  // weight: gain compensation compares the two there.
  MapEntries secondary;
  std::vector<uint16_t> primary_weight;
  // Blend with gain compensation: the output pixels (row-major indices) where gain
  // estimation compares the primary and secondary cameras (core/gain/overlap_samples.h).
  std::vector<uint32_t> gain_samples;
  // Size of each rig camera's image, as calibrated (apply() checks inputs against it).
  std::vector<cv::Size> camera_sizes;
  std::vector<std::string> camera_names;
  std::vector<bool> camera_used;  // does any pixel read from camera i?
  // Footprint-aware sampling: the deepest pyramid level any pixel reads from camera i
  // (0 or empty: none, apply() samples the images as they come). See footprint.h.
  std::vector<uint8_t> camera_levels;

  bool empty() const { return primary.empty(); }
  double coverage() const;  // fraction of pixels some camera sees
};

// kAdaptive (the default) evaluates the camera models exactly on an 8-pixel grid and
// interpolates inside blocks where that is provably within 0.05 px (see adaptive/bands.h);
// kExact evaluates every pixel. A blend map is interpolated only where a single camera
// sees the block; where cameras overlap every pixel is exact.
enum class MapPrecision { kAdaptive, kExact };

// kFootprint (the default) moves entries whose output pixel covers 4 or more camera
// pixels (along its shorter axis) to a pre-filtered pyramid level (footprint.h); kBilinear samples the full-size
// images everywhere. Maps of views that do not shrink are the same either way.
enum class Sampling { kFootprint, kBilinear };

// Builds the map for `view` over `rig`, using the view's fusion policy. Runs on OpenCV's
// thread pool (cv::setNumThreads sets its size). Throws std::invalid_argument if the
// view's frame is not connected to the cameras or the rig has more than 254 cameras.
// `occlusion` (optional, one entry per rig camera): a camera whose covering depth hides a
// pixel's surface point does not compete for it, so a point every camera sees hidden is
// black. The adaptive builder interpolates on measured depth and with occlusion only where
// the surface is smooth between its samples and no occluder's edge crosses the block
// (adaptive/bands.cc, may_interpolate).
// `feathers` (optional, blend only): the cameras' feather weights made beforehand; used
// where they fit the rig and the view's feather_px, else made here.
FusionMap build_map(const Rig& rig, const View& view, MapPrecision precision = MapPrecision::kAdaptive,
                    Sampling sampling = Sampling::kFootprint, const Occlusion* occlusion = nullptr,
                    const FeatherSet* feathers = nullptr);

}  // namespace omniview

// Footprint-aware sampling for views that shrink the cameras.
//
// Where an output pixel covers several camera pixels (a small panorama of a big lens, a
// bird's-eye view's far field), sampling the full-size image bilinearly aliases. Such map
// entries instead address a pre-filtered level of an image pyramid (cv::pyrDown, a
// 5-tap Gaussian per octave): level L where the footprint's shorter axis spans 2^(L+1) to
// 2^(L+2) camera pixels (one level finer than mip-mapping's floor rule, as the Gaussian and
// the bilinear tap at level L already average over ~2^(L+1) pixels; on the golden
// panoramas this measured best). apply() builds the pyramid once per frame, only for the
// cameras and levels a map reads. Views that shrink less than 4x keep every entry at level
// 0 and pay nothing.
#pragma once

#include <opencv2/core/mat.hpp>

#include "core/map/fusion_map.h"

namespace omniview {

inline constexpr int kMaxPyramidLevel = 3;

// Size of a camera image at pyramid level `level` (cv::pyrDown's rounding).
cv::Size pyramid_level_size(cv::Size full, int level);

// Moves the entries of a nearest-centre map whose footprint spans 4 or more camera pixels
// to the matching pyramid level, and fills map.camera_levels. Footprints are
// measured on a 4-pixel grid (the map is smooth inside a camera's region).
void assign_footprint_levels(FusionMap& map);

}  // namespace omniview

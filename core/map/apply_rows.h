// The per-pixel rows of apply_map (apply.cc): one output row each, from a FusionMap's
// entries and the camera images as Sources. Not part of the public API.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/map/fusion_map.h"

namespace omniview::apply_internal {

// One camera image (or one of its pyramid levels), continuous.
struct Source {
  const uint8_t* data = nullptr;
  size_t stride = 0;  // bytes per row; images are continuous, so width * channels
  int channels = 0;
  int rows = 0;
  uint32_t last_footprint = 0;  // offset of the footprint whose bottom-right is the last pixel
};

// Any map: blends, gains (`lut`: one 256-entry table per camera and output channel, or
// null), grey and colour sources mixed; `oc` output channels (1 or 3). Writes n pixels of
// the row starting at map entry `first`.
void apply_row_general(const FusionMap& map, size_t first, const Source* sources, const uint8_t* lut, int n, int oc,
                       uint8_t* out);

// Nearest-centre maps whose sources all have the output's channel count: the hot path.
// sources[cam + level * cameras]: each camera's image, then its pyramid levels (footprint.h).
void apply_row_uniform_bgr(const MapEntry* m, const Source* sources, int cameras, int n, uint8_t* out);
void apply_row_uniform_grey(const MapEntry* m, const Source* sources, int cameras, int n, uint8_t* out);

}  // namespace omniview::apply_internal

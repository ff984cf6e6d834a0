// The per-pixel rows of apply_map (apply.cc), portable: GCC/Clang vector extensions, built
// for baseline x86-64 and x86-64-v3. ThreadSanitizer builds compile this file without its
// per-access instrumentation (core/CMakeLists.txt says why); apply_map declares the memory
// these rows touch to it instead.
#include "core/map/apply_rows.h"

#include <cstdint>
#include <cstring>

#include "core/map/multiversion.h"

namespace omniview::apply_internal {
namespace {

// Colour pixels are interpolated with GCC/Clang vector extensions: eight 16-bit lanes
// hold a pixel and its right neighbour (B G R x B' G' R' x), which maps onto SSE2 on
// x86-64 and NEON on ARM64 with no per-platform code. Two linear steps in 1/256 keep every
// lane below 255 * 256 + 128, so nothing overflows.
using U8x8 = uint8_t __attribute__((vector_size(8)));
using U16x8 = uint16_t __attribute__((vector_size(16)));

// Loads pixel p and the one to its right, 4 bytes each: reads one byte past the pair.
[[gnu::always_inline]] inline U16x8 load_pair(const uint8_t* p) {
  uint32_t left, right;
  std::memcpy(&left, p, 4);
  std::memcpy(&right, p + 3, 4);
  const uint64_t both = left | (uint64_t{right} << 32);
  U8x8 v;
  std::memcpy(&v, &both, 8);
  return __builtin_convertvector(v, U16x8);
}

[[gnu::always_inline]] inline U16x8 lerp_pair(U16x8 pair, U16x8 weights) {  // lanes 0-2: left (1 - f) + right f, in 1/256
  const U16x8 w = pair * weights;
  return (w + __builtin_shufflevector(w, w, 4, 5, 6, 7, 0, 1, 2, 3) + 128) >> 8;
}

// Plain per-channel version for the image's very last footprint, where load_pair's extra
// byte would lie past the end of the image.
[[gnu::always_inline]] inline void bilinear3_edge(const Source& s, const MapEntry& e, uint8_t* out) {
  const uint8_t* p = s.data + size_t{e.offset} * 3;
  const uint32_t fx = e.fx, fy = e.fy;
  for (int c = 0; c < 3; ++c) {
    const uint32_t top = p[c] * (256 - fx) + p[c + 3] * fx;
    const uint32_t bottom = p[s.stride + c] * (256 - fx) + p[s.stride + c + 3] * fx;
    out[c] = static_cast<uint8_t>((top * (256 - fy) + bottom * fy + 32768) >> 16);
  }
}

// Horizontal weight vectors {256 - fx x4, fx x4} for every fx: one 4 KiB table in L1
// instead of building the vector per pixel.
struct HorizontalWeights {
  alignas(16) U16x8 table[256];
  HorizontalWeights() {
    for (uint16_t fx = 0; fx < 256; ++fx) {
      const uint16_t gx = 256 - fx;
      table[fx] = U16x8{gx, gx, gx, gx, fx, fx, fx, fx};
    }
  }
};
const HorizontalWeights kHorizontalWeights;

// Writes 4 bytes to out: the pixel and a byte the next pixel overwrites (the caller keeps
// the row's last pixel off this path).
[[gnu::always_inline]] inline void bilinear3(const Source& s, const MapEntry& e, uint8_t* out) {
  if (e.offset >= s.last_footprint) return bilinear3_edge(s, e, out);
  const uint8_t* p = s.data + size_t{e.offset} * 3;
  const U16x8 wx = kHorizontalWeights.table[e.fx];
  const U16x8 top = lerp_pair(load_pair(p), wx);
  const U16x8 bottom = lerp_pair(load_pair(p + s.stride), wx);
  const uint16_t fy = e.fy;
  const U16x8 v = (top * static_cast<uint16_t>(256 - fy) + bottom * fy + 128) >> 8;
  const U8x8 bytes = __builtin_convertvector(v, U8x8);
  std::memcpy(out, &bytes, 4);
}

[[gnu::always_inline]] inline uint8_t bilinear1(const Source& s, const MapEntry& e) {
  const uint8_t* p = s.data + e.offset;
  const uint32_t fx = e.fx, fy = e.fy;
  const uint32_t top = p[0] * (256 - fx) + p[1] * fx;
  const uint32_t bottom = p[s.stride] * (256 - fx) + p[s.stride + 1] * fx;
  return static_cast<uint8_t>((top * (256 - fy) + bottom * fy + 32768) >> 16);
}

// One pixel from any source into `out_channels` channels: the mixed grey/colour path.
inline void sample_any(const Source& s, const MapEntry& e, int out_channels, uint8_t* out) {
  if (s.channels == 3) {
    uint8_t bgr[4];
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
// sources[cam + level * cameras]: each camera's image, then its pyramid levels (footprint.h).
[[gnu::always_inline]] inline void apply_row_uniform(const MapEntry* m, const Source* sources, int cameras, int n,
                                                     uint8_t* out) {
  for (int i = 0; i < n; ++i, out += C) {
    const MapEntry e = m[i];
    if (e.cam == kNoCamera) {
      std::memset(out, 0, C);
    } else if constexpr (C == 3) {
      if (i + 1 < n) {
        bilinear3(sources[e.cam + e.level * cameras], e, out);  // 4-byte store; the next pixel overwrites the 4th
      } else {
        uint8_t last[4];
        bilinear3(sources[e.cam + e.level * cameras], e, last);
        std::memcpy(out, last, 3);
      }
    } else {
      out[0] = bilinear1(sources[e.cam + e.level * cameras], e);
    }
  }
}

// Gains as one 256-entry table per camera and output channel, applied to each sample after
// interpolation (a gain is linear, so this equals interpolating gained images, up to
// rounding). Only blend maps carry gains, and they take these general rows anyway, so the
// nearest-centre hot paths (AVX2 included) are untouched. Measured against the
// alternatives on a 1024x512 blend (bench/gain_bench.cc): cv::LUT over the input images
// costs a pass over every input pixel (~0.15 ms per 640x480 grey image, 0.8 ms per colour
// one, whose 3-channel tables OpenCV does not vectorise), more than the look-ups here;
// scaling the blend weights by the gains needs a saturating 32-bit multiply per channel
// and was no faster. The tables (5 cameras x 3 x 256 bytes) stay in L1.
template <int OC>
[[gnu::always_inline]] inline void apply_lut(const uint8_t* __restrict lut, int cam, uint8_t* __restrict px) {
  const uint8_t* __restrict table = lut + static_cast<size_t>(cam) * OC * 256;
  uint8_t v[OC];
  for (int c = 0; c < OC; ++c) v[c] = table[c * 256 + px[c]];
  for (int c = 0; c < OC; ++c) px[c] = v[c];
}

// Compiled per output channel count and with or without gains, so the loops over channels
// unroll and the rows without gains run exactly as before.
template <int OC, bool kGains>
void apply_row_general(const FusionMap& map, size_t first, const Source* sources, const uint8_t* __restrict lut, int n,
                       uint8_t* __restrict out) {
  const bool blend = !map.secondary.empty();
  const int cameras = static_cast<int>(map.camera_sizes.size());
  for (int i = 0; i < n; ++i, out += OC) {
    const MapEntry& e = map.primary[first + i];
    if (e.cam == kNoCamera) {
      std::memset(out, 0, OC);
      continue;
    }
    sample_any(sources[e.cam + e.level * cameras], e, OC, out);
    if constexpr (kGains) apply_lut<OC>(lut, e.cam, out);
    if (!blend) continue;
    const MapEntry& e2 = map.secondary[first + i];
    const uint32_t w = map.primary_weight[first + i];
    if (e2.cam == kNoCamera || w >= 256) continue;
    uint8_t other[3];
    sample_any(sources[e2.cam + e2.level * cameras], e2, OC, other);
    if constexpr (kGains) apply_lut<OC>(lut, e2.cam, other);
    for (int c = 0; c < OC; ++c) out[c] = static_cast<uint8_t>((out[c] * w + other[c] * (256 - w) + 128) >> 8);
  }
}

}  // namespace

void apply_row_general(const FusionMap& map, size_t first, const Source* sources, const uint8_t* lut, int n, int oc,
                       uint8_t* out) {
  if (oc == 3) {
    lut ? apply_row_general<3, true>(map, first, sources, lut, n, out)
        : apply_row_general<3, false>(map, first, sources, lut, n, out);
  } else {
    lut ? apply_row_general<1, true>(map, first, sources, lut, n, out)
        : apply_row_general<1, false>(map, first, sources, lut, n, out);
  }
}

// The hot paths, built for baseline x86-64 and x86-64-v3 (see multiversion.h).
OMNIVIEW_MULTIVERSION
void apply_row_uniform_bgr(const MapEntry* m, const Source* sources, int cameras, int n, uint8_t* out) {
  apply_row_uniform<3>(m, sources, cameras, n, out);
}
OMNIVIEW_MULTIVERSION
void apply_row_uniform_grey(const MapEntry* m, const Source* sources, int cameras, int n, uint8_t* out) {
  apply_row_uniform<1>(m, sources, cameras, n, out);
}

}  // namespace omniview::apply_internal

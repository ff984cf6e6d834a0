#include "core/map/apply.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/map/apply_avx2.h"
#include "core/map/multiversion.h"

namespace omniview {
namespace {

struct Source {
  const uint8_t* data = nullptr;
  size_t stride = 0;  // bytes per row; images are continuous, so width * channels
  int channels = 0;
  int rows = 0;
  uint32_t last_footprint = 0;  // offset of the footprint whose bottom-right is the last pixel
};

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

// Writes 4 bytes to out: the pixel and a byte the next pixel overwrites (the caller keeps
// the row's last pixel off this path).
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

#ifdef OMNIVIEW_APPLY_AVX2
// The AVX2 rows address every camera from one base pointer with 32-bit offsets: true if
// the used images lie close enough together (they do when the allocator maps them near
// each other, as glibc does; otherwise the portable rows run).
bool make_gather_sources(const std::vector<Source>& sources, apply_internal::GatherSources& g) {
  if (sources.size() > 8) return false;
  uintptr_t lo = UINTPTR_MAX, hi = 0;
  for (size_t i = 0; i < sources.size(); ++i) {
    if (sources[i].data == nullptr) continue;
    const auto start = reinterpret_cast<uintptr_t>(sources[i].data);
    lo = std::min(lo, start);
    hi = std::max(hi, start + sources[i].stride * static_cast<size_t>(sources[i].rows));
  }
  if (hi == 0 || hi - lo >= (uintptr_t{1} << 31)) return false;
  g.base = reinterpret_cast<const uint8_t*>(lo);
  for (size_t i = 0; i < sources.size(); ++i) {
    if (sources[i].data == nullptr) continue;
    g.delta[i] = static_cast<int32_t>(reinterpret_cast<uintptr_t>(sources[i].data) - lo);
    g.stride[i] = static_cast<int32_t>(sources[i].stride);
    g.last_wide[i] = g.delta[i] + static_cast<int32_t>(sources[i].stride * sources[i].rows) - 8;
  }
  return true;
}
#endif

std::atomic<bool> g_simd_enabled{true};

}  // namespace

namespace apply_internal {
void set_simd_enabled(bool enabled) { g_simd_enabled = enabled; }
bool simd_enabled() { return g_simd_enabled; }
}  // namespace apply_internal

void apply_map(const FusionMap& map, const std::vector<cv::Mat>& images, cv::Mat& out, int out_channels) {
  apply_map(map, images, out, out_channels, CameraGains{});
}

void apply_map(const FusionMap& map, const std::vector<cv::Mat>& images, cv::Mat& out, int out_channels,
               const CameraGains& gains) {
  if (out_channels != 1 && out_channels != 3) {
    throw std::invalid_argument("output must have 1 or 3 channels, not " + std::to_string(out_channels));
  }
  std::vector<uint8_t> lut;
  if (!gains.empty()) {
    if (gains.channels != out_channels || gains.cameras() != map.camera_sizes.size() ||
        gains.gain.size() != gains.cameras() * static_cast<size_t>(out_channels)) {
      throw std::invalid_argument("gains are for " + std::to_string(gains.cameras()) + " camera(s) and " +
                                  std::to_string(gains.channels) + " channel(s), the view has " +
                                  std::to_string(map.camera_sizes.size()) + " and " + std::to_string(out_channels));
    }
    lut.resize(gains.gain.size() * 256);
    for (size_t t = 0; t < gains.gain.size(); ++t) {
      const float g = std::isfinite(gains.gain[t]) ? std::max(gains.gain[t], 0.0f) : 1.0f;
      for (int v = 0; v < 256; ++v) lut[t * 256 + v] = cv::saturate_cast<uint8_t>(g * static_cast<float>(v));
    }
  }
  if (images.size() != map.camera_sizes.size()) {
    throw std::invalid_argument("expected " + std::to_string(map.camera_sizes.size()) + " images (one per camera), got " +
                                std::to_string(images.size()));
  }
  // Camera i at pyramid level l is source i + l * cameras (footprint.h).
  const size_t cameras = images.size();
  int levels = 0;
  for (size_t i = 0; i < map.camera_levels.size(); ++i) levels = std::max<int>(levels, map.camera_levels[i]);
  std::vector<Source> sources(cameras * (levels + 1));
  std::vector<cv::Mat> continuous(sources.size());
  bool uniform = map.secondary.empty() && lut.empty();  // the fast rows know no gains
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
    uniform = uniform && img.channels() == out_channels;
  }
  // The pyramid levels this map reads, built once per frame (each camera in parallel).
  cv::parallel_for_(cv::Range(0, static_cast<int>(cameras)), [&](const cv::Range& r) {
    for (int i = r.start; i < r.end; ++i) {
      const int deepest = map.camera_levels.empty() || !map.camera_used[i] ? 0 : map.camera_levels[i];
      for (int l = 1; l <= deepest; ++l) cv::pyrDown(continuous[i + (l - 1) * cameras], continuous[i + l * cameras]);
    }
  });
  for (size_t i = 0; i < sources.size(); ++i) {
    const cv::Mat& img = continuous[i];
    if (img.empty()) continue;
    sources[i] = Source{img.data, img.step[0], img.channels(), img.rows,
                        static_cast<uint32_t>((img.rows - 2) * img.cols + img.cols - 2)};
  }
  out.create(map.height, map.width, out_channels == 3 ? CV_8UC3 : CV_8UC1);
  const int w = map.width;
#ifdef OMNIVIEW_APPLY_AVX2
  static const bool avx2 = apply_internal::have_avx2();
  apply_internal::GatherSources gather;
  const bool use_avx2 = avx2 && apply_internal::simd_enabled() && uniform && make_gather_sources(sources, gather);
#else
  const bool use_avx2 = false;
#endif
  // A few stripes per thread: large enough that neighbours share no output cache line in
  // the middle of their work, small enough to even out a loaded core.
  const int stripes = std::min(map.height, 8 * std::max(1, cv::getNumThreads()));
  cv::parallel_for_(cv::Range(0, map.height), [&](const cv::Range& rows) {
    for (int row = rows.start; row < rows.end; ++row) {
      const size_t first = static_cast<size_t>(row) * w;
      uint8_t* dst = out.ptr<uint8_t>(row);
#ifdef OMNIVIEW_APPLY_AVX2
      if (use_avx2) {
        if (out_channels == 3) {
          apply_internal::apply_row_bgr_avx2(&map.primary[first], w, gather, static_cast<int>(cameras), dst);
        } else {
          apply_internal::apply_row_grey_avx2(&map.primary[first], w, gather, static_cast<int>(cameras), dst);
        }
        continue;
      }
#endif
      if (uniform && out_channels == 3) {
        apply_row_uniform_bgr(&map.primary[first], sources.data(), static_cast<int>(cameras), w, dst);
      } else if (uniform) {
        apply_row_uniform_grey(&map.primary[first], sources.data(), static_cast<int>(cameras), w, dst);
      } else {
        apply_row_general(map, first, sources.data(), lut.empty() ? nullptr : lut.data(), w, out_channels, dst);
      }
    }
  }, stripes);
}

}  // namespace omniview

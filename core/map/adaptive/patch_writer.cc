#include "core/map/adaptive/patch_writer.h"

#include <cstring>

#include "core/map/multiversion.h"

namespace omniview::map_internal {
namespace {

// GCC/Clang vector extensions: SSE2 (two halves) in the baseline build, AVX2 in the
// x86-64-v3 clone, NEON on ARM64, from one source.
constexpr int kLanes = 8;
using Floats = float __attribute__((vector_size(4 * kLanes)));
using Ints = int32_t __attribute__((vector_size(4 * kLanes)));
using Words = uint32_t __attribute__((vector_size(4 * kLanes)));

// encode() (map_kernels.h) on eight samples of one camera, same arithmetic lane by lane;
// writes the eight entries.
[[gnu::always_inline]] inline void encode8(const SampleLimits& c, Floats u, Floats v, uint32_t cam, MapEntry* out) {
  const Floats zero{}, max_u = zero + c.max_u, max_v = zero + c.max_v;
  Floats uc = u > zero ? u : zero, vc = v > zero ? v : zero;  // NaN -> 0, as encode()
  uc = uc < max_u ? uc : max_u;
  vc = vc < max_v ? vc : max_v;
  const Floats max_x0 = zero + c.max_x0, max_y0 = zero + c.max_y0;
  const Ints x0 = __builtin_convertvector(uc < max_x0 ? uc : max_x0, Ints);
  const Ints y0 = __builtin_convertvector(vc < max_y0 ? vc : max_y0, Ints);
  const Floats fx = (uc - __builtin_convertvector(x0, Floats)) * 256.0f + 0.5f;
  const Floats fy = (vc - __builtin_convertvector(y0, Floats)) * 256.0f + 0.5f;
  const Floats cap = zero + 255.0f;
  const Ints fxi = __builtin_convertvector(fx < cap ? fx : cap, Ints);
  const Ints fyi = __builtin_convertvector(fy < cap ? fy : cap, Ints);
  const Words offset = __builtin_convertvector(y0 * c.width_px + x0, Words);
  const Words rest = __builtin_convertvector(fxi | (fyi << 8), Words) | (cam << 16);
  // MapEntry = {offset, fx fy cam level} as two little-endian 32-bit words.
  const Words lo = __builtin_shufflevector(offset, rest, 0, 8, 1, 9, 2, 10, 3, 11);
  const Words hi = __builtin_shufflevector(offset, rest, 4, 12, 5, 13, 6, 14, 7, 15);
  static_assert(sizeof(lo) == 4 * sizeof(MapEntry));
  std::memcpy(out, &lo, sizeof(lo));
  std::memcpy(out + 4, &hi, sizeof(hi));
}

}  // namespace

OMNIVIEW_MULTIVERSION
void write_patches(const std::vector<Patch>& patches, const std::vector<CameraSetup>& setups, FusionMap& map) {
  Floats lane;
  for (int i = 0; i < kLanes; ++i) lane[i] = static_cast<float>(i);
  for (const Patch& p : patches) {
    const SampleLimits& limits = setups[p.cam].limits;
    const float inv_w = 1.0f / static_cast<float>(p.x1 - p.x0), inv_h = 1.0f / static_cast<float>(p.y1 - p.y0);
    const int n = p.x_end - p.x_begin;
    for (int y = p.y_begin; y < p.y_end; ++y) {
      // Patch::fill_row's arithmetic, so every path interpolates the same bits.
      const float ty = static_cast<float>(y - p.y0) * inv_h;
      const float ul = p.u00 + (p.u01 - p.u00) * ty, ur = p.u10 + (p.u11 - p.u10) * ty;
      const float vl = p.v00 + (p.v01 - p.v00) * ty, vr = p.v10 + (p.v11 - p.v10) * ty;
      const float du = (ur - ul) * inv_w, dv = (vr - vl) * inv_w;
      MapEntry* out = &map.primary[static_cast<size_t>(y) * map.width + p.x_begin];
      for (int x = 0; x < n; x += kLanes) {
        const Floats t = lane + static_cast<float>(p.x_begin + x - p.x0);
        if (n - x >= kLanes) {
          encode8(limits, ul + du * t, vl + dv * t, p.cam, out + x);
        } else {  // a patch's narrow remainder: encode all lanes, keep the ones inside
          MapEntry tail[kLanes];
          encode8(limits, ul + du * t, vl + dv * t, p.cam, tail);
          std::memcpy(out + x, tail, (n - x) * sizeof(MapEntry));
        }
      }
    }
  }
}

}  // namespace omniview::map_internal

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
  MapEntry* const entries = map.primary.data();
  const size_t width = static_cast<size_t>(map.width);
  for (const Patch& p : patches) {
    // Copies: the compiler cannot tell that the entries written do not overlap them.
    const SampleLimits limits = setups[p.cam].limits;
    const uint32_t cam = p.cam;
    const int n = p.x_end - p.x_begin, first_t = p.x_begin - p.x0;
    for (int y = p.y_begin; y < p.y_end; ++y) {
      const Patch::Row r = p.row(y);  // Patch::fill_row's arithmetic, lane by lane
      MapEntry* out = entries + static_cast<size_t>(y) * width + p.x_begin;
      for (int x = 0; x < n; x += kLanes) {
        const Floats t = lane + static_cast<float>(first_t + x);
        const Floats u = r.ua + t * (r.ub + t * r.uc), v = r.va + t * (r.vb + t * r.vc);
        if (n - x >= kLanes) {
          encode8(limits, u, v, cam, out + x);
        } else {  // a patch's narrow remainder: encode all lanes, keep the ones inside
          MapEntry tail[kLanes];
          encode8(limits, u, v, cam, tail);
          std::memcpy(out + x, tail, (n - x) * sizeof(MapEntry));
        }
      }
    }
  }
}

}  // namespace omniview::map_internal

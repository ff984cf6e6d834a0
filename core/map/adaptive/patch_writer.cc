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

// Coordinates u = a + t (b + t c) per lane, encoded into `count` entries (<= kLanes).
struct Lanes {
  Floats ua, ub, uc, va, vb, vc, t;

  static Lanes of(const Patch::Row& r, Floats t) {
    const Floats zero{};
    return {zero + r.ua, zero + r.ub, zero + r.uc, zero + r.va, zero + r.vb, zero + r.vc, t};
  }
  // Lanes 0-3 from `left`, 4-7 from `right`.
  static Lanes join(const Lanes& l, const Lanes& r) {
#define OMNIVIEW_HALVES(field) __builtin_shufflevector(l.field, r.field, 0, 1, 2, 3, 12, 13, 14, 15)
    return {OMNIVIEW_HALVES(ua), OMNIVIEW_HALVES(ub), OMNIVIEW_HALVES(uc), OMNIVIEW_HALVES(va),
            OMNIVIEW_HALVES(vb), OMNIVIEW_HALVES(vc), OMNIVIEW_HALVES(t)};
#undef OMNIVIEW_HALVES
  }

  [[gnu::always_inline]] void write(const SampleLimits& limits, uint32_t cam, MapEntry* out, int count) const {
    const Floats u = ua + t * (ub + t * uc), v = va + t * (vb + t * vc);
    if (count == kLanes) {
      encode8(limits, u, v, cam, out);
    } else {  // a patch's narrow remainder: encode all lanes, keep the ones inside
      MapEntry tail[kLanes];
      encode8(limits, u, v, cam, tail);
      std::memcpy(out, tail, count * sizeof(MapEntry));
    }
  }
};

// Two patches side by side over the same rows and camera, the left one 4 pixels wide (a
// block's quarters): written as one 8-lane row instead of two half-empty ones.
bool pairs(const Patch& left, const Patch& right) {
  return left.x_end == right.x_begin && left.x_end - left.x_begin == kLanes / 2 &&
         right.x_end - right.x_begin >= kLanes / 2 && left.y_begin == right.y_begin && left.y_end == right.y_end &&
         left.cam == right.cam;
}

}  // namespace

OMNIVIEW_MULTIVERSION
void write_patches(const std::vector<Patch>& patches, const std::vector<CameraSetup>& setups, FusionMap& map) {
  Floats lane;
  for (int i = 0; i < kLanes; ++i) lane[i] = static_cast<float>(i);
  MapEntry* const entries = map.primary.data();
  const size_t width = static_cast<size_t>(map.width);
  for (size_t i = 0; i < patches.size(); ++i) {
    const Patch& p = patches[i];
    // Copies: the compiler cannot tell that the entries written do not overlap them.
    const SampleLimits limits = setups[p.cam].limits;
    const uint32_t cam = p.cam;
    if (i + 1 < patches.size() && pairs(p, patches[i + 1])) {
      const Patch& q = patches[++i];
      const int q_rest = q.x_end - q.x_begin - kLanes / 2;  // the last block's extra column
      for (int y = p.y_begin; y < p.y_end; ++y) {
        MapEntry* out = entries + static_cast<size_t>(y) * width + p.x_begin;
        const Patch::Row rq = q.row(y);
        Lanes::join(Lanes::of(p.row(y), lane + static_cast<float>(p.x_begin - p.x0)),
                    Lanes::of(rq, lane + static_cast<float>(q.x_begin - q.x0 - kLanes / 2)))
            .write(limits, cam, out, kLanes);
        if (q_rest > 0) {
          Lanes::of(rq, lane + static_cast<float>(q.x_begin + kLanes / 2 - q.x0)).write(limits, cam, out + kLanes, q_rest);
        }
      }
      continue;
    }
    const int n = p.x_end - p.x_begin;
    const Floats t0 = lane + static_cast<float>(p.x_begin - p.x0);  // the patch's first 8 columns
    for (int y = p.y_begin; y < p.y_end; ++y) {
      MapEntry* out = entries + static_cast<size_t>(y) * width + p.x_begin;
      // Patch::row's arithmetic; bilinear rows skip the zero quadratic terms.
      Floats u, v;
      if (!p.quadratic) {
        const float s = static_cast<float>(y - p.y0);
        const float ua = p.cu[0][0] + s * p.cu[0][1], ub = p.cu[1][0] + s * p.cu[1][1];
        const float va = p.cv[0][0] + s * p.cv[0][1], vb = p.cv[1][0] + s * p.cv[1][1];
        u = ua + t0 * ub, v = va + t0 * vb;
        if (n == kLanes) {  // a whole 8x8 block: the common case
          encode8(limits, u, v, cam, out);
          continue;
        }
      }
      const Patch::Row r = p.row(y);
      for (int x = 0; x < n; x += kLanes) {
        const Floats t = t0 + static_cast<float>(x);
        u = r.ua + t * (r.ub + t * r.uc), v = r.va + t * (r.vb + t * r.vc);
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

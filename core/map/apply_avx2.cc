#include "core/map/apply_avx2.h"

#ifdef OMNIVIEW_APPLY_AVX2

#include <immintrin.h>

namespace omniview::apply_internal {
namespace {

// Scalar twins of the vector arithmetic below (same rounding, bit for bit) for a row's
// last few pixels. pmulhrsw: (a * b + 2^14) >> 15.
inline int mulhrs(int a, int b) { return (a * b + (1 << 14)) >> 15; }

inline void bgr_pixel(const MapEntry& e, const GatherSources& s, int cameras, uint8_t* out) {
  if (e.cam == kNoCamera) {
    out[0] = out[1] = out[2] = 0;
    return;
  }
  const int source = e.cam + e.level * cameras;
  const uint8_t* top = s.base + s.delta[source] + static_cast<size_t>(e.offset) * 3;
  const uint8_t* bottom = top + s.stride[source];
  const int fx = e.fx << 7, fy = e.fy << 7;
  for (int c = 0; c < 3; ++c) {
    const int ht = (top[c] << 6) + mulhrs((top[c + 3] - top[c]) << 6, fx);
    const int hb = (bottom[c] << 6) + mulhrs((bottom[c + 3] - bottom[c]) << 6, fx);
    out[c] = static_cast<uint8_t>((ht + mulhrs(hb - ht, fy) + 32) >> 6);
  }
}

inline uint8_t grey_pixel(const MapEntry& e, const GatherSources& s, int cameras) {
  if (e.cam == kNoCamera) return 0;
  const int source = e.cam + e.level * cameras;
  const uint8_t* top = s.base + s.delta[source] + e.offset;
  const uint8_t* bottom = top + s.stride[source];
  const int fx = e.fx, fy = e.fy;
  const int left = top[0] * (256 - fy) + bottom[0] * fy, right = top[1] * (256 - fy) + bottom[1] * fy;
  return static_cast<uint8_t>((left * 256 + (right - left) * fx + 32768) >> 16);
}

// Eight map entries as offsets and (fx | fy << 8 | cam << 16 | level << 24) words, in
// pixel order.
struct Entries8 {
  __m256i offset, rest;
};

// Which source each entry reads (cam + level * cameras), and which entries are black.
__attribute__((target("avx2"), always_inline)) inline __m256i source_index(__m256i rest, __m256i cameras,
                                                                           __m256i& black) {
  const __m256i cam = _mm256_and_si256(_mm256_srli_epi32(rest, 16), _mm256_set1_epi32(0xFF));
  black = _mm256_cmpeq_epi32(cam, _mm256_set1_epi32(kNoCamera));
  return _mm256_add_epi32(cam, _mm256_mullo_epi32(_mm256_srli_epi32(rest, 24), cameras));
}

__attribute__((target("avx2"), always_inline)) inline Entries8 load_entries(const MapEntry* m) {
  const __m256i a = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(m));      // pixels 0-3
  const __m256i b = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(m + 4));  // pixels 4-7
  // Per 128-bit lane: offsets then rests of its two pixels.
  const __m256i as = _mm256_shuffle_epi32(a, _MM_SHUFFLE(3, 1, 2, 0));
  const __m256i bs = _mm256_shuffle_epi32(b, _MM_SHUFFLE(3, 1, 2, 0));
  // 64-bit pairs (0,1) (4,5) | (2,3) (6,7), put back in order.
  return {_mm256_permute4x64_epi64(_mm256_unpacklo_epi64(as, bs), _MM_SHUFFLE(3, 1, 2, 0)),
          _mm256_permute4x64_epi64(_mm256_unpackhi_epi64(as, bs), _MM_SHUFFLE(3, 1, 2, 0))};
}

}  // namespace

bool have_avx2() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
}

// Colour: per pixel and row one 8-byte gather (B G R B' G' R' and two bytes more); where
// those two bytes would lie past the image's end, two 4-byte gathers at the footprint's
// first byte (B G R B') and two bytes on (R B' G' R'), so no image needs padding. Interpolation in 16-bit lanes in 1/64 of a level: horizontal, then vertical,
// each one pmulhrsw with the 8-bit fraction.
__attribute__((target("avx2"))) void apply_row_bgr_avx2(const MapEntry* m, int n, const GatherSources& s,
                                                        int cameras, uint8_t* out) {
  const __m256i camera_count = _mm256_set1_epi32(cameras);
  const __m256i delta = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(s.delta));
  const __m256i stride = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(s.stride));
  const __m256i low3 = _mm256_set1_epi32(0x00FFFFFF);
  const __m256i zero = _mm256_setzero_si256();
  const __m256i round = _mm256_set1_epi16(32);
  // Each pixel's fx (byte 0 of its rest word) and fy (byte 1) into its four bytes.
  const __m256i spread_fx = _mm256_setr_epi8(0, 0, 0, 0, 4, 4, 4, 4, 8, 8, 8, 8, 12, 12, 12, 12,
                                             0, 0, 0, 0, 4, 4, 4, 4, 8, 8, 8, 8, 12, 12, 12, 12);
  const __m256i spread_fy = _mm256_add_epi8(spread_fx, _mm256_set1_epi8(1));
  // BGRx BGRx BGRx BGRx -> 12 packed bytes per lane; then both lanes' 12 bytes together.
  const __m256i pack3 = _mm256_setr_epi8(0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, -1, -1, -1, -1,
                                         0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, -1, -1, -1, -1);
  const __m256i join = _mm256_setr_epi32(0, 1, 2, 4, 5, 6, 7, 7);
  const __m256i last_wide = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(s.last_wide));
  const __m256i split = _mm256_setr_epi8(0, 1, 2, -1, 8, 9, 10, -1, 3, 4, 5, -1, 11, 12, 13, -1,
                                         0, 1, 2, -1, 8, 9, 10, -1, 3, 4, 5, -1, 11, 12, 13, -1);
  const int* base = reinterpret_cast<const int*>(s.base);
  const long long* base64 = reinterpret_cast<const long long*>(s.base);
  int i = 0;
  for (; i + 8 <= n; i += 8, out += 24) {
    const Entries8 e = load_entries(m + i);
    __m256i black;
    const __m256i cam = source_index(e.rest, camera_count, black);
    const __m256i offset3 = _mm256_add_epi32(e.offset, _mm256_slli_epi32(e.offset, 1));
    const __m256i top = _mm256_andnot_si256(black, _mm256_add_epi32(offset3, _mm256_permutevar8x32_epi32(delta, cam)));
    const __m256i bottom = _mm256_andnot_si256(black, _mm256_add_epi32(top, _mm256_permutevar8x32_epi32(stride, cam)));
    // Left pixel B G R 0, right pixel B' G' R' 0, per 32-bit lane, in pixel order.
    __m256i tl, tr, bl, br;
    const __m256i unsafe = _mm256_cmpgt_epi32(bottom, _mm256_permutevar8x32_epi32(last_wide, cam));
    if (_mm256_testz_si256(unsafe, unsafe)) {
      // Usually: one 8-byte gather per pixel and row (half the elements of 4-byte gathers).
      const __m256i qt0 = _mm256_i32gather_epi64(base64, _mm256_castsi256_si128(top), 1);        // pixels 0-3
      const __m256i qt1 = _mm256_i32gather_epi64(base64, _mm256_extracti128_si256(top, 1), 1);   // pixels 4-7
      const __m256i qb0 = _mm256_i32gather_epi64(base64, _mm256_castsi256_si128(bottom), 1);
      const __m256i qb1 = _mm256_i32gather_epi64(base64, _mm256_extracti128_si256(bottom, 1), 1);
      // Per lane [L(a) L(b) R(a) R(b)]; then pixel order across both gathers.
      const __m256i ta = _mm256_shuffle_epi8(qt0, split), tb = _mm256_shuffle_epi8(qt1, split);
      const __m256i ba = _mm256_shuffle_epi8(qb0, split), bb = _mm256_shuffle_epi8(qb1, split);
      constexpr int kOrder = _MM_SHUFFLE(3, 1, 2, 0);
      tl = _mm256_permute4x64_epi64(_mm256_unpacklo_epi64(ta, tb), kOrder);
      tr = _mm256_permute4x64_epi64(_mm256_unpackhi_epi64(ta, tb), kOrder);
      bl = _mm256_permute4x64_epi64(_mm256_unpacklo_epi64(ba, bb), kOrder);
      br = _mm256_permute4x64_epi64(_mm256_unpackhi_epi64(ba, bb), kOrder);
    } else {
      // Footprints at an image's very end: 4-byte reads that stay inside the footprint.
      const __m256i two = _mm256_set1_epi32(2);
      const __m256i t0 = _mm256_i32gather_epi32(base, top, 1);
      const __m256i t2 = _mm256_i32gather_epi32(base, _mm256_add_epi32(top, two), 1);
      const __m256i b0 = _mm256_i32gather_epi32(base, bottom, 1);
      const __m256i b2 = _mm256_i32gather_epi32(base, _mm256_add_epi32(bottom, two), 1);
      tl = _mm256_and_si256(t0, low3), bl = _mm256_and_si256(b0, low3);
      tr = _mm256_or_si256(_mm256_srli_epi32(t0, 24), _mm256_slli_epi32(_mm256_srli_epi32(t2, 16), 8));
      br = _mm256_or_si256(_mm256_srli_epi32(b0, 24), _mm256_slli_epi32(_mm256_srli_epi32(b2, 16), 8));
    }
    // Weights fx << 7 and fy << 7 per 16-bit lane.
    const __m256i fxb = _mm256_shuffle_epi8(e.rest, spread_fx), fyb = _mm256_shuffle_epi8(e.rest, spread_fy);
    __m256i result[2];
    for (int half = 0; half < 2; ++half) {
#define widen(v) (half == 0 ? _mm256_unpacklo_epi8(v, zero) : _mm256_unpackhi_epi8(v, zero))
      const __m256i fx = _mm256_slli_epi16(widen(fxb), 7), fy = _mm256_slli_epi16(widen(fyb), 7);
      const __m256i l0 = _mm256_slli_epi16(widen(tl), 6), r0 = _mm256_slli_epi16(widen(tr), 6);
      const __m256i l1 = _mm256_slli_epi16(widen(bl), 6), r1 = _mm256_slli_epi16(widen(br), 6);
      const __m256i ht = _mm256_add_epi16(l0, _mm256_mulhrs_epi16(_mm256_sub_epi16(r0, l0), fx));
      const __m256i hb = _mm256_add_epi16(l1, _mm256_mulhrs_epi16(_mm256_sub_epi16(r1, l1), fx));
      const __m256i v = _mm256_add_epi16(ht, _mm256_mulhrs_epi16(_mm256_sub_epi16(hb, ht), fy));
      result[half] = _mm256_srli_epi16(_mm256_add_epi16(v, round), 6);
#undef widen
    }
    const __m256i bgrx = _mm256_andnot_si256(black, _mm256_packus_epi16(result[0], result[1]));
    const __m256i packed = _mm256_permutevar8x32_epi32(_mm256_shuffle_epi8(bgrx, pack3), join);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm256_castsi256_si128(packed));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out + 16), _mm256_extracti128_si256(packed, 1));
  }
  for (; i < n; ++i, out += 3) bgr_pixel(m[i], s, cameras, out);
}

// Grey: the top pair gathered at the footprint, the bottom pair as the last two bytes of
// a gather two bytes earlier (no read past the image's last pixel). Vertical first with
// pmaddwd in 1/256, then horizontal in 32 bits.
__attribute__((target("avx2"))) void apply_row_grey_avx2(const MapEntry* m, int n, const GatherSources& s,
                                                         int cameras, uint8_t* out) {
  const __m256i camera_count = _mm256_set1_epi32(cameras);
  const __m256i delta = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(s.delta));
  const __m256i stride = _mm256_sub_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(s.stride)),
                                          _mm256_set1_epi32(2));
  const __m256i byte_mask = _mm256_set1_epi32(0xFF);
  const __m256i even_bytes = _mm256_set1_epi32(0x00FF00FF);
  const __m256i full = _mm256_set1_epi32(256);
  const __m256i round = _mm256_set1_epi32(32768);
  const __m256i gather_words = _mm256_setr_epi32(0, 4, 1, 1, 1, 1, 1, 1);
  const int* base = reinterpret_cast<const int*>(s.base);
  int i = 0;
  for (; i + 8 <= n; i += 8, out += 8) {
    const Entries8 e = load_entries(m + i);
    __m256i black;
    const __m256i cam = source_index(e.rest, camera_count, black);
    const __m256i top = _mm256_andnot_si256(black, _mm256_add_epi32(e.offset, _mm256_permutevar8x32_epi32(delta, cam)));
    const __m256i bottom = _mm256_add_epi32(top, _mm256_andnot_si256(black, _mm256_permutevar8x32_epi32(stride, cam)));
    const __m256i t = _mm256_i32gather_epi32(base, top, 1);     // t0 t1 . .
    const __m256i b = _mm256_i32gather_epi32(base, bottom, 1);  // . . b0 b1
    const __m256i tb = _mm256_blend_epi16(t, b, 0xAA);          // t0 t1 b0 b1
    const __m256i left = _mm256_and_si256(tb, even_bytes);      // words t0, b0
    const __m256i right = _mm256_and_si256(_mm256_srli_epi32(tb, 8), even_bytes);  // words t1, b1
    const __m256i fx = _mm256_and_si256(e.rest, byte_mask);
    const __m256i fy = _mm256_and_si256(_mm256_srli_epi32(e.rest, 8), byte_mask);
    const __m256i wy = _mm256_or_si256(_mm256_sub_epi32(full, fy), _mm256_slli_epi32(fy, 16));  // words 256-fy, fy
    const __m256i l = _mm256_madd_epi16(left, wy), r = _mm256_madd_epi16(right, wy);
    const __m256i v = _mm256_add_epi32(_mm256_slli_epi32(l, 8), _mm256_mullo_epi32(_mm256_sub_epi32(r, l), fx));
    const __m256i g = _mm256_andnot_si256(black, _mm256_srli_epi32(_mm256_add_epi32(v, round), 16));
    const __m256i bytes = _mm256_packus_epi16(_mm256_packus_epi32(g, g), g);  // lane k: its 4 pixels in dword 0
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out),
                     _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(bytes, gather_words)));
  }
  for (; i < n; ++i) *out++ = grey_pixel(m[i], s, cameras);
}

}  // namespace omniview::apply_internal

#endif

// A patch of output pixels whose source coordinates are interpolated from exact samples:
// bilinear from its four corners, or biquadratic from a 3x3 lattice (corners, edge
// midpoints, centre) where a block curves too much for bilinear.
#pragma once

#include <cstdint>

namespace omniview::map_internal {

// 1.0f / n, from a table for the spans patches have (a division per patch showed up in
// profiles); the same bits as the division.
inline float reciprocal(int n) {
  static const struct Table {
    float values[9];
    Table() {
      for (int i = 0; i < 9; ++i) values[i] = 1.0f / static_cast<float>(i);
    }
  } table;
  return n >= 0 && n < 9 ? table.values[n] : 1.0f / static_cast<float>(n);
}

struct Patch {
  int x0, x1, y0, y1;                  // the samples' extent: columns x0..x1, rows y0..y1
  int x_begin, x_end, y_begin, y_end;  // the pixels it covers
  uint32_t cam;
  bool quadratic;          // samples on the 3x3 lattice; else at the corners [0|2][0|2] only
  float u[3][3], v[3][3];  // [row][column]: row 0 at y0, 2 at y1; column 0 at x0, 2 at x1
  float inv_w, inv_h;      // 1 / (x1 - x0), 1 / (y1 - y0): once per patch, not per row

  // u and v are left for the caller to fill (bilinear: the corners only).
  Patch(int x0, int x1, int y0, int y1, int x_begin, int x_end, int y_begin, int y_end, uint32_t cam, bool quadratic)
      : x0(x0), x1(x1), y0(y0), y1(y1), x_begin(x_begin), x_end(x_end), y_begin(y_begin), y_end(y_end), cam(cam),
        quadratic(quadratic), inv_w(reciprocal(x1 - x0)), inv_h(reciprocal(y1 - y0)) {}

  // Along row y the coordinates are u = ua + t (ub + t uc), v likewise, t = x - x0.
  struct Row {
    float ua, ub, uc, va, vb, vc;
  };

  Row row(int y) const {
    const float ty = static_cast<float>(y - y0) * inv_h;
    if (!quadratic) {
      const float ul = u[0][0] + (u[2][0] - u[0][0]) * ty, ur = u[0][2] + (u[2][2] - u[0][2]) * ty;
      const float vl = v[0][0] + (v[2][0] - v[0][0]) * ty, vr = v[0][2] + (v[2][2] - v[0][2]) * ty;
      return Row{ul, (ur - ul) * inv_w, 0.0f, vl, (vr - vl) * inv_w, 0.0f};
    }
    // Lagrange weights of the rows at ty = 0, 1/2, 1; then the quadratic through the
    // three columns' values, in powers of t.
    const float w0 = 2 * (ty - 0.5f) * (ty - 1), w1 = -4 * ty * (ty - 1), w2 = 2 * ty * (ty - 0.5f);
    Row r;
    const auto along = [&](const float (&s)[3][3], float& a, float& b, float& c) {
      float k[3];
      for (int i = 0; i < 3; ++i) k[i] = w0 * s[0][i] + w1 * s[1][i] + w2 * s[2][i];
      a = k[0];
      b = (-3 * k[0] + 4 * k[1] - k[2]) * inv_w;
      c = (2 * k[0] - 4 * k[1] + 2 * k[2]) * (inv_w * inv_w);
    };
    along(u, r.ua, r.ub, r.uc);
    along(v, r.va, r.vb, r.vc);
    return r;
  }

  // Row y's pixels into u, v, at index (output column - origin).
  void fill_row(int y, float* __restrict out_u, float* __restrict out_v, int origin) const {
    const Row r = row(y);
    for (int x = x_begin; x < x_end; ++x) {
      const float t = static_cast<float>(x - x0);
      out_u[x - origin] = r.ua + t * (r.ub + t * r.uc);
      out_v[x - origin] = r.va + t * (r.vb + t * r.vc);
    }
  }
};

}  // namespace omniview::map_internal

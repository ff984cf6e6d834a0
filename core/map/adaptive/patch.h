// A patch of output pixels whose source coordinates are interpolated from exact samples:
// bilinear from its four corners, or biquadratic from a 3x3 lattice (corners, edge
// midpoints, centre) where a block curves too much for bilinear. Evaluated as polynomials
// in the pixel offsets, so a row costs a few multiply-adds.
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
  // The same as polynomials: u = sum cu[i][j] t^i s^j, t = x - x0, s = y - y0 (finish()).
  float cu[3][3], cv[3][3];

  // u and v are left for the caller to fill (bilinear: the corners only), then finish().
  Patch(int x0, int x1, int y0, int y1, int x_begin, int x_end, int y_begin, int y_end, uint32_t cam, bool quadratic)
      : x0(x0), x1(x1), y0(y0), y1(y1), x_begin(x_begin), x_end(x_end), y_begin(y_begin), y_end(y_end), cam(cam),
        quadratic(quadratic) {}

  void finish() {
    to_polynomial(u, cu);
    to_polynomial(v, cv);
  }

  // Along row y the coordinates are u = ua + t (ub + t uc), v likewise, t = x - x0.
  struct Row {
    float ua, ub, uc, va, vb, vc;
  };

  Row row(int y) const {
    const float s = static_cast<float>(y - y0);
    const auto at = [s](const float (&c)[3]) { return c[0] + s * (c[1] + s * c[2]); };
    return Row{at(cu[0]), at(cu[1]), at(cu[2]), at(cv[0]), at(cv[1]), at(cv[2])};
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

 private:
  // Coefficients of powers 0, 1, 2 of the interpolant through f0, f1, f2 at 0, h/2, h
  // (linear: through f0 and f2), with inv = 1 / h.
  void along(float f0, float f1, float f2, float inv, float (&c)[3]) const {
    if (quadratic) {
      c[0] = f0, c[1] = (-3 * f0 + 4 * f1 - f2) * inv, c[2] = (2 * f0 - 4 * f1 + 2 * f2) * (inv * inv);
    } else {
      c[0] = f0, c[1] = (f2 - f0) * inv, c[2] = 0;
    }
  }

  // Along x within each sample row, then each power's coefficients along y.
  void to_polynomial(const float (&nodes)[3][3], float (&c)[3][3]) const {
    const float inv_w = reciprocal(x1 - x0), inv_h = reciprocal(y1 - y0);
    float by_row[3][3] = {};  // [sample row][power of t]
    for (int r = 0; r < 3; ++r) {
      if (quadratic || r != 1) along(nodes[r][0], quadratic ? nodes[r][1] : 0.0f, nodes[r][2], inv_w, by_row[r]);
    }
    for (int i = 0; i < 3; ++i) along(by_row[0][i], by_row[1][i], by_row[2][i], inv_h, c[i]);
  }
};

}  // namespace omniview::map_internal

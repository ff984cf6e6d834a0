// Branch-free elementary functions the compiler can vectorise.
//
// The map builder projects millions of points per view change in float; libm's atan2
// is scalar and, at ~20 ns a call, alone would take longer than our whole budget. These
// are plain polynomials and selects, so GCC and Clang turn loops over them into SIMD.
// Double-precision callers (tests, unprojection, the API) use libm instead.
#pragma once

#include <cmath>
#include <type_traits>

namespace omniview::fast {

// atan(x) for x in [0, 1]; minimax odd polynomial, |error| < 4e-8 rad in exact arithmetic
// (< 3e-7 rad evaluated in float, atan2_nonneg_y included).
template <typename S>
inline S atan_unit(S x) {
  const S x2 = x * x;
  S p = S(-0.0040540580);
  p = p * x2 + S(0.0218612288);
  p = p * x2 + S(-0.0559098861);
  p = p * x2 + S(0.0964200441);
  p = p * x2 + S(-0.1390853351);
  p = p * x2 + S(0.1994653599);
  p = p * x2 + S(-0.3332985605);
  p = p * x2 + S(0.9999993329);
  return p * x;
}

// atan2(y, x) for y >= 0 (the only case camera models need: y is a radius), in [0, pi].
template <typename S>
inline S atan2_nonneg_y(S y, S x) {
  const S ax = x < S(0) ? -x : x;
  const S num = y < ax ? y : ax;
  const S den = y < ax ? ax : y;
  // den == 0 only at the origin, where any angle will do.
  const S t = atan_unit(num / (den > S(0) ? den : S(1)));
  const S a = y > ax ? S(M_PI_2) - t : t;
  return x < S(0) ? S(M_PI) - a : a;
}

template <typename S>
inline S atan2_radius(S r, S z) {
  if constexpr (std::is_same_v<S, double>) {
    return std::atan2(r, z);
  } else {
    return atan2_nonneg_y(r, z);
  }
}

// atan(x) for x >= 0.
template <typename S>
inline S atan_nonneg(S x) {
  if constexpr (std::is_same_v<S, double>) {
    return std::atan(x);
  } else {
    return atan2_nonneg_y(x, S(1));
  }
}

// cos(x) and sin(x)/x for x in [0, pi], from x^2: Taylor series to x^18, whose
// truncation error at pi is below 2e-8.
template <typename S>
inline void cos_and_sinc(S x2, S& cos_x, S& sinc_x) {
  // Coefficients (-1)^k / (2k)! and (-1)^k / (2k+1)!, k = 9 down to 0, for Horner in x^2.
  constexpr double kCos[] = {-1.0 / 6402373705728000.0, 1.0 / 20922789888000.0, -1.0 / 87178291200.0,
                             1.0 / 479001600.0, -1.0 / 3628800.0, 1.0 / 40320.0, -1.0 / 720.0,
                             1.0 / 24.0, -1.0 / 2.0, 1.0};
  constexpr double kSinc[] = {-1.0 / 121645100408832000.0, 1.0 / 355687428096000.0, -1.0 / 1307674368000.0,
                              1.0 / 6227020800.0, -1.0 / 39916800.0, 1.0 / 362880.0, -1.0 / 5040.0,
                              1.0 / 120.0, -1.0 / 6.0, 1.0};
  S c = S(kCos[0]), s = S(kSinc[0]);
  for (int k = 1; k < 10; ++k) {
    c = c * x2 + S(kCos[k]);
    s = s * x2 + S(kSinc[k]);
  }
  cos_x = c;
  sinc_x = s;
}

}  // namespace omniview::fast

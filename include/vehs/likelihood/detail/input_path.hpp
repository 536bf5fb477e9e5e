#pragma once
// The recorded input between two samples, as a cubic in s = (t − t_k)/Δt ∈ [0, 1]:
//   zero-order hold  u_k                                 (a DAC without reconstruction filter)
//   linear           u_k + s (u_{k+1} − u_k)
//   cubic            Catmull–Rom: the cubic Hermite with slopes (u_{k+1} − u_{k−1})/2 at the ends
//   band-limited     the cubic through u_k, u_{k+1} and the windowed-sinc (Lanczos, a = 8)
//                    interpolants at s = 1/3 and 2/3 (a signal band-limited below Nyquist, as
//                    the anti-aliased input of a measured rig)
// Records are extended at their ends by repeating the end samples.
#include <array>
#include <cmath>
#include <cstddef>

#include "vehs/likelihood/filter.hpp"

namespace vehs::likelihood::detail {

using InputCubic = std::array<double, 4>;  ///< u(s) = c0 + c1 s + c2 s² + c3 s³

inline double input_at(const double* u, std::size_t n, long i) {
  return u[i < 0 ? 0 : (i >= long(n) ? n - 1 : std::size_t(i))];
}

/// Lanczos-windowed sinc interpolation of u at fractional index k + s.
inline double band_limited_at(const double* u, std::size_t n, std::size_t k, double s) {
  constexpr int a = 8;
  constexpr double pi = 3.14159265358979323846;
  double sum = 0.0, wsum = 0.0;
  for (int j = -a + 1; j <= a; ++j) {
    const double d = s - j;  // distance from sample k + j
    double w = 1.0;
    if (std::abs(d) > 1e-12) w = a * std::sin(pi * d) * std::sin(pi * d / a) / (pi * pi * d * d);
    sum += w * input_at(u, n, long(k) + j);
    wsum += w;
  }
  return sum / wsum;
}

/// The input over interval [t_k, t_{k+1}] of a record u[0 … n) (k + 1 < n).
inline InputCubic input_cubic(const double* u, std::size_t n, std::size_t k, InputInterpolation how) {
  const double u0 = input_at(u, n, long(k)), u1 = input_at(u, n, long(k) + 1);
  switch (how) {
    case InputInterpolation::ZeroOrderHold: return {u0, 0.0, 0.0, 0.0};
    case InputInterpolation::Linear: return {u0, u1 - u0, 0.0, 0.0};
    case InputInterpolation::Cubic: {
      const double um = input_at(u, n, long(k) - 1), u2 = input_at(u, n, long(k) + 2);
      const double m0 = 0.5 * (u1 - um), m1 = 0.5 * (u2 - u0);
      return {u0, m0, 3.0 * (u1 - u0) - 2.0 * m0 - m1, 2.0 * (u0 - u1) + m0 + m1};
    }
    case InputInterpolation::BandLimited: {
      const double a = band_limited_at(u, n, k, 1.0 / 3.0), b = band_limited_at(u, n, k, 2.0 / 3.0);
      // cubic through (0, u0), (1/3, a), (2/3, b), (1, u1)
      const double c1 = (-11.0 * u0 + 18.0 * a - 9.0 * b + 2.0 * u1) / 2.0;
      const double c2 = 9.0 * (2.0 * u0 - 5.0 * a + 4.0 * b - u1) / 2.0;
      const double c3 = 27.0 * (-u0 + 3.0 * a - 3.0 * b + u1) / 6.0;
      return {u0, c1, c2, c3};
    }
  }
  return {u0, 0.0, 0.0, 0.0};
}

inline double eval_cubic(const InputCubic& c, double s) {
  return c[0] + s * (c[1] + s * (c[2] + s * c[3]));
}

}  // namespace vehs::likelihood::detail

#pragma once
// Expectations of the dictionary's functions under a Gaussian state, generic over the scalar
// type (double or ceres::Jet): the building blocks of the assumed-density time update
// (moment_system.hpp). Every formula is exact for a Gaussian; non-smooth functions (sign(y),
// y·|y|, the hinge of an end stop) have smooth expectations, so the filter and its automatic
// derivatives stay smooth where an extended Kalman filter would see a kink or a zero slope.
#include <array>
#include <cmath>

#include "vehs/likelihood/detail/flatten.hpp"

namespace vehs::likelihood::detail {

inline constexpr double kSqrt2 = 1.4142135623730950488;
inline constexpr double kInvSqrt2Pi = 0.39894228040143267794;  // 1/sqrt(2π)

/// Raw moments E[x^a y^b] of a bivariate Gaussian for a ≤ A, b ≤ B, by Stein's identity
/// E[x g] = m_x E[g] + P_xx E[∂_x g] + P_xy E[∂_y g] (and likewise for y).
template <class T>
class GaussianMoments {
 public:
  static constexpr int kMaxA = 16;  ///< powers of x up to 15
  static constexpr int kMaxB = 6;   ///< powers of y up to 5

  /// Fills M(a, b) for b ≤ B and a ≤ a_max[b] (a_max non-increasing in b, a_max[b] ≥ 0).
  VEHS_FLATTEN void compute(const T& mx, const T& my, const T& pxx, const T& pxy, const T& pyy,
                            const int* a_max, int B) {
    at(0, 0) = T(1.0);
    for (int a = 0; a < a_max[0]; ++a) {
      at(a + 1, 0) = mx * at(a, 0);
      if (a > 0) at(a + 1, 0) += (double(a) * pxx) * at(a - 1, 0);
    }
    for (int b = 0; b < B && a_max[b + 1] >= 0; ++b)
      for (int a = 0; a <= a_max[b + 1]; ++a) {
        T v = my * at(a, b);
        if (a > 0) v += (double(a) * pxy) * at(a - 1, b);
        if (b > 0) v += (double(b) * pyy) * at(a, b - 1);
        at(a, b + 1) = v;
      }
  }
  /// The full table up to a ≤ A, b ≤ B.
  void compute(const T& mx, const T& my, const T& pxx, const T& pxy, const T& pyy, int A, int B) {
    int a_max[kMaxB];
    for (int b = 0; b < kMaxB; ++b) a_max[b] = b <= B ? A : -1;
    compute(mx, my, pxx, pxy, pyy, a_max, B);
  }
  const T& operator()(int a, int b) const { return m_[a * kMaxB + b]; }

 private:
  T& at(int a, int b) { return m_[a * kMaxB + b]; }
  std::array<T, kMaxA * kMaxB> m_{};
};

/// Standard normal density and distribution function.
template <class T>
T normal_pdf(const T& d) {
  using std::exp;
  return kInvSqrt2Pi * exp(-0.5 * d * d);
}
template <class T>
T normal_cdf(const T& d) {
  using std::erfc;
  return 0.5 * erfc(-d / kSqrt2);
}

/// For y ~ N(m, s²): E[sign y] and E[∂_y sign y] = 2·density at 0.
template <class T>
T expect_sign(const T& m, const T& s) {
  using std::erf;
  return erf(m / (kSqrt2 * s));
}
template <class T>
T expect_dsign(const T& m, const T& s) {
  return 2.0 * normal_pdf(T(m / s)) / s;
}
/// E[y·|y|] = (m² + s²)·erf(m/(√2 s)) + 2 m s φ(m/s).
template <class T>
T expect_y_abs_y(const T& m, const T& s) {
  const T d = m / s;
  return (m * m + s * s) * expect_sign(m, s) + 2.0 * m * s * normal_pdf(d);
}
/// E[|y|] = 2 s φ(m/s) + m·erf(m/(√2 s)); ∂_y(y|y|) = 2|y|.
template <class T>
T expect_abs(const T& m, const T& s) {
  return 2.0 * s * normal_pdf(T(m / s)) + m * expect_sign(m, s);
}
/// For x ~ N(m, s²): E[(x − g)⁺] = (m − g)Φ(d) + s φ(d), d = (m − g)/s; E[1{x > g}] = Φ(d).
template <class T>
T expect_hinge(const T& m, const T& s, const T& g) {
  const T d = (m - g) / s;
  return (m - g) * normal_cdf(d) + s * normal_pdf(d);
}
template <class T>
T expect_step(const T& m, const T& s, const T& g) {
  return normal_cdf(T((m - g) / s));
}

}  // namespace vehs::likelihood::detail

#pragma once
// The stiff fallback of the filter's time update: backward Euler on the moment equations,
//     s_{n+1} = s_n + h·f(t_{n+1}, s_{n+1}),
// solved by damped Newton in double precision with a finite-difference Jacobian, the
// derivatives (ceres::Jet parts) then from two Newton corrections in T at the solution (the
// implicit function theorem: the Jet part of the fixed point solves J·ṡ = ṡ_n + h·∂_θ f).
//
// Why: Coulomb friction's expected slope μ·2φ(0)/√P_yy grows without bound as the velocity
// becomes nearly known (nearly deterministic, quantised closed-loop motion), and an impact stop's
// wall is as stiff as k_stop; explicit steps then leave the model's domain at any affordable
// count. Backward Euler is L-stable and, for the covariance equation dP/dt = A P + P Aᵀ + Q, its
// step (I − h·L_A)⁻¹ is the resolvent of a positive semigroup: covariances stay valid. It is
// first order, so the filter uses it only on an interval whose RK4 steps fail at every count.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <type_traits>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "vehs/likelihood/detail/moment_system.hpp"
#include "vehs/likelihood/detail/scalar.hpp"

namespace vehs::likelihood::detail {

/// The values of a coefficient set (derivative parts dropped).
template <class T>
Coefficients<double> coefficient_values(const Coefficients<T>& c) {
  Coefficients<double> v;
  for (const T& a : c.drift) v.drift.push_back(value_of(a));
  for (const T& a : c.diffusion) v.diffusion.push_back(value_of(a));
  v.stop = {value_of(c.stop.k_stop), value_of(c.stop.gap), value_of(c.stop.gap_neg)};
  v.forcing = {value_of(c.forcing.amplitude), value_of(c.forcing.omega), value_of(c.forcing.phase)};
  v.lambda = value_of(c.lambda);
  v.coupling = value_of(c.coupling);
  v.tau = value_of(c.tau);
  v.intensity = value_of(c.intensity);
  v.measurement_var = value_of(c.measurement_var);
  return v;
}

/// Backward Euler steps of a MomentSystem<T, D>, with the same equations in double for Newton.
template <class T, int D>
class ImplicitPropagator {
 public:
  using Pk = Packing<D>;
  static constexpr int N = Pk::size;
  using State = PackedState<T, D>;
  using Vec = Eigen::Matrix<double, N, 1>;
  using Mat = Eigen::Matrix<double, N, N>;

  ImplicitPropagator(const Structure& st, const Coefficients<T>& c)
      : values_(coefficient_values(c)), sys_v_(st, values_) {}
  ImplicitPropagator(const ImplicitPropagator&) = delete;  // sys_v_ refers to values_
  ImplicitPropagator& operator=(const ImplicitPropagator&) = delete;

  /// `steps` backward Euler steps over [t0, t0 + duration] (the drive already set on `sys` and
  /// given again here for the double system). False when a Newton solve fails.
  bool propagate(const MomentSystem<T, D>& sys, double t0, double duration, int steps, const InputCubic& u,
                 State& s) {
    sys_v_.set_drive(t0, duration, u);
    const double h = duration / steps;
    for (int i = 0; i < steps; ++i)
      if (!adaptive_step(sys, t0 + i * h, h, 0, s)) return false;
    return true;
  }

 private:
  static constexpr int kMaxNewton = 30;
  static constexpr int kMaxHalvings = 12;
  static constexpr int kMaxDepth = 4;  ///< a step whose Newton solve fails is halved up to 2^4 times

  /// One step from t to t + h; where its Newton solve fails, two steps of h/2.
  bool adaptive_step(const MomentSystem<T, D>& sys, double t, double h, int depth, State& s) const {
    const State start = s;
    if (step(sys, t + h, h, s)) return true;
    if (depth == kMaxDepth) return false;
    s = start;
    return adaptive_step(sys, t, 0.5 * h, depth + 1, s) && adaptive_step(sys, t + 0.5 * h, 0.5 * h, depth + 1, s);
  }

  /// The size against which component j of a state is measured: for a mean √P_jj + |m_j|, for
  /// a covariance √(P_ii·P_jj) + |P_ij|; at least 1e-10 of the largest of its kind (a variance
  /// that is exactly zero, x's at the start of a record without sensor noise, has no size of its
  /// own).
  static Vec scales(const Vec& z) {
    Vec w;
    double mean_max = 0.0, cov_max = 0.0;
    for (int i = 0; i < D; ++i) {
      w[i] = std::sqrt(std::abs(z[Pk::p(i, i)])) + std::abs(z[i]);
      mean_max = std::max(mean_max, w[i]);
    }
    for (int i = 0; i < D; ++i)
      for (int j = i; j < D; ++j) {
        const int k = Pk::p(i, j);
        w[k] = std::sqrt(std::abs(z[Pk::p(i, i)] * z[Pk::p(j, j)])) + std::abs(z[k]);
        cov_max = std::max(cov_max, w[k]);
      }
    for (int i = 0; i < D; ++i) w[i] = std::max(w[i], 1e-10 * mean_max);
    for (int k = D; k < N; ++k) w[k] = std::max(w[k], 1e-10 * cov_max);
    return w;
  }
  static double merit(const Vec& g, const Vec& w) {
    double m = 0.0;
    for (int j = 0; j < N; ++j)
      if (g[j] != 0.0) m += (g[j] / w[j]) * (g[j] / w[j]);
    return m;
  }
  /// g = z − s0 − h·f(t, z); false outside the domain or not finite.
  bool residual(double t, double h, const Vec& s0, const Vec& z, Vec& g) const {
    Vec f;
    if (!sys_v_(t, z, f)) return false;
    g = z - s0 - h * f;
    return g.allFinite();
  }
  /// The Jacobian of the residual at z by forward differences (backward where forward leaves the
  /// domain).
  bool jacobian(double t, double h, const Vec& s0, const Vec& z, const Vec& g, const Vec& w, Mat& J) const {
    for (int j = 0; j < N; ++j) {
      const double d = w[j] > 0.0 ? 1e-7 * w[j] : 1e-7;
      Vec zp = z, gp;
      zp[j] += d;
      if (residual(t, h, s0, zp, gp)) {
        J.col(j) = (gp - g) / d;
        continue;
      }
      zp[j] = z[j] - d;
      if (!residual(t, h, s0, zp, gp)) return false;
      J.col(j) = (g - gp) / d;
    }
    return J.allFinite();
  }

  bool step(const MomentSystem<T, D>& sys, double t, double h, State& s) const {
    Vec s0;
    for (int j = 0; j < N; ++j) s0[j] = value_of(s[j]);
    Vec z = s0, g;
    if (!residual(t, h, s0, z, g)) return false;
    Mat J;
    bool converged = false;
    for (int it = 0; it < kMaxNewton && !converged; ++it) {
      const Vec w = scales(z);
      if (!jacobian(t, h, s0, z, g, w, J)) return false;
      const Vec dz = J.partialPivLu().solve(-g);
      if (!dz.allFinite()) return false;
      const double m0 = merit(g, w);
      double a = 1.0;
      bool moved = false;
      for (int k = 0; k < kMaxHalvings && !moved; ++k, a *= 0.5) {
        const Vec zn = z + a * dz;
        Vec gn;
        if (residual(t, h, s0, zn, gn) && merit(gn, w) < m0) z = zn, g = gn, moved = true;
      }
      if (!moved) return m0 < 1e-24 && damped(J) && finish(sys, t, h, z, J, s);
      converged = merit(g, w) < 1e-24;  // residual below 1e-12 of the state's scales
      if (converged) break;
      converged = true;
      const Vec wn = scales(z);
      for (int j = 0; j < N; ++j)
        if (std::abs(a * dz[j]) > 1e-12 * wn[j]) converged = false;
    }
    return converged && damped(J) && finish(sys, t, h, z, J, s);
  }

  /// Whether the step is one backward Euler takes rightly: no eigenvalue of h·∂f/∂s = I − J has
  /// a real part above 1/2. Backward Euler damps growth as well as decay (its factor 1/(1 − hλ)
  /// turns sign beyond hλ = 1), so on an explosive model (a drift that pushes the state out, the
  /// moment equations' finite-time blow-up) it would return a bounded, wrong law; such a step is
  /// halved, and fails where the growth is real.
  static bool damped(const Mat& J) {
    const Mat hf = Mat::Identity() - J;
    const Eigen::EigenSolver<Mat> es(hf, false);
    if (es.info() != Eigen::Success) return false;
    return es.eigenvalues().real().maxCoeff() <= 0.5;
  }

  /// The new state: the values z; for Jets the derivative parts by two Newton corrections of
  /// z − s − h·f(t, z) in T with the Jacobian J.
  bool finish(const MomentSystem<T, D>& sys, double t, double h, const Vec& z, const Mat& J, State& s) const {
    if constexpr (std::is_same_v<T, double>) {
      (void)sys, (void)J;
      s = z;
      return true;
    } else {
      const Mat Jinv = J.inverse();
      if (!Jinv.allFinite()) return false;
      State zt;
      for (int j = 0; j < N; ++j) zt[j] = s[j] + T(z[j] - value_of(s[j]));
      for (int pass = 0; pass < 2; ++pass) {
        State f, corr;
        if (!sys(t, zt, f)) return false;
        State gt;
        for (int j = 0; j < N; ++j) gt[j] = zt[j] - s[j] - h * f[j];
        for (int i = 0; i < N; ++i) {
          T acc{};
          for (int j = 0; j < N; ++j)
            if (Jinv(i, j) != 0.0) acc += Jinv(i, j) * gt[j];
          corr[i] = acc;
        }
        for (int i = 0; i < N; ++i) zt[i] -= corr[i];
      }
      s = zt;
      return true;
    }
  }

  Coefficients<double> values_;
  MomentSystem<double, D> sys_v_;
};

}  // namespace vehs::likelihood::detail

#pragma once
// The continuous–discrete Gaussian filter over one block of samples (a record, or a piece of a
// long record), generic over the scalar type T and the state dimension D.
//
// Start: the block is conditioned on its first sample — x ~ N(x_0, measurement variance) (a
// diffuse prior updated with x_0), y ~ N(0, y_prior_var) (data-based, the same for every
// parameter value); with electromechanical_coupling or colored_noise (y, v, η) from the
// stationary law of the model linearised at x_0, given x_0 (hidden_prior.hpp), or where that has
// none y as above, v ~ N(0, v_prior_var) and η from its own stationary law N(0, intensity/2τ).
// Then for k = 1 … n−1: time update over [t_{k−1}, t_k] by RK4 substeps of the moment equations
// (the drive held or interpolated over [t_{k−1}, t_k], input_path.hpp; an interval whose steps
// leave the domain is redone with finer substeps, and where the finest still leaves it, by
// exponential_step's linearised steps that keep the covariance positive semi-definite), measurement update with
// x_k = x(t_k) + ε_k: innovation e_k = x_k − m_x, S_k = P_xx + σ_ε², log-likelihood
// −½(log 2πS_k + e_k²/S_k), Kalman gain P_{·x}/S_k.
#include <cmath>
#include <algorithm>
#include <cstddef>

#include "vehs/likelihood/detail/hidden_prior.hpp"
#include "vehs/likelihood/detail/moment_system.hpp"
#include "vehs/likelihood/ode.hpp"

namespace vehs::likelihood::detail {

struct BlockData {
  const double* x = nullptr;
  std::size_t n = 0;
  /// The whole record's input (null without a drive term) and this block's first index in it
  /// (interpolation near the block's ends uses the neighbouring samples).
  const double* record_u = nullptr;
  std::size_t record_n = 0, first = 0;
  double t0 = 0.0, dt = 0.0;  ///< time of the first sample, sampling interval
  double y_prior_var = 1.0;   ///< prior variance of y at the first sample
  double v_prior_var = 0.0;   ///< prior variance of v at the first sample
};

struct FilterSettings {
  int substeps = 4;
  InputInterpolation input = InputInterpolation::ZeroOrderHold;
};

/// Where and why the filter stopped (no number is returned then).
struct FilterFailure {
  bool failed = false;
  std::size_t sample = 0;  ///< index within the block
  const char* what = "";
};

/// A sink that ignores every sample.
struct NoSink {
  template <class T, class S>
  void operator()(std::size_t, const T&, const T&, const T&, const S&) {}
};

inline constexpr double kLog2Pi = 1.8378770664093454836;

/// Finer substeps tried, as multiples of the settings' count, on an interval whose RK4 steps
/// left the domain: a stiff spot the automatic count does not see (Coulomb friction's slope
/// μ·2φ(0)/√P_yy when the velocity is nearly known, an impact stop's wall). Only that interval
/// pays; an interval that fails even at the finest is a divergence.
inline constexpr int kSubstepRefinements[] = {4, 16, 64};

/// Square-matrix product out = a·b (fixed-size, element loops: the scalar may be a Jet).
template <class M>
void small_product(const M& a, const M& b, M& out) {
  for (int i = 0; i < a.rows(); ++i)
    for (int j = 0; j < b.cols(); ++j) {
      auto v = a(i, 0) * b(0, j);
      for (int k = 1; k < a.cols(); ++k) v += a(i, k) * b(k, j);
      out(i, j) = v;
    }
}

/// exp(a) of a matrix with a small norm (≤ 0.4 here) by its Taylor series to degree 12
/// (remainder below 1e-15 of the norm's power).
template <class M>
M small_expm(const M& a) {
  M e = M::Identity(), term = M::Identity(), next;
  for (int k = 1; k <= 12; ++k) {
    small_product(term, a, next);
    for (int i = 0; i < a.rows(); ++i)
      for (int j = 0; j < a.cols(); ++j) next(i, j) *= 1.0 / double(k);
    term = next;
    e += term;
  }
  return e;
}

/// Adds w·Φ G Φᵀ (Φ the top-left D×D block of `e`) to `q`: a positive semi-definite term.
template <int D, class M, class N>
void add_sandwich(const M& e, const N& g, double w, N& q) {
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) {
      auto v = q(i, j);
      for (int k = 0; k < D; ++k)
        for (int l = 0; l < D; ++l) v += w * (e(i, k) * g(k, l) * e(j, l));
      q(i, j) = v;
    }
}

/// The fallback time update over [t, t + h] for intervals whose RK4 steps leave the domain
/// (Coulomb friction's sign(y) in nearly deterministic motion: its expected slope
/// μ·2φ(0)/√P_yy grows without bound as the velocity becomes known, so the moment equations are
/// stiff beyond any affordable RK4 step). The moment equations are linearised at the state —
/// rates b = E[f], Jacobian F = E[∂f], noise G = E[G Gᵀ] — and stepped exactly for that linear
/// system (an exponential Rosenbrock–Euler step): m += h φ₁(hF) b,
/// P = Φ P Φᵀ + ∫₀ʰ Φ(τ) G Φ(τ)ᵀ dτ with Φ = exp(hF). Every term of the covariance update is a
/// congruence or a positively weighted sum of them, so P stays symmetric positive semi-definite
/// at any stiffness, and a stiff mode relaxes to its equilibrium instead of overshooting.
/// exp is taken of [[hF, hb], [0, 0]] by scaling (2^−J, J ≤ 60: the cost grows with the log of
/// the stiffness) and squaring; the noise integral by a 3-point rule with positive weights on the
/// geometric intervals [τ, 2τ] (nodes τ, √2τ, 2τ) that the squarings visit, plus [0, τ_min].
template <int D, class Sys, class State>
bool exponential_step(const Sys& sys, double t, double h, State& s) {
  using Pk = Packing<D>;
  using T = typename State::Scalar;
  using Aug = Eigen::Matrix<T, D + 1, D + 1>;
  using Mat = Eigen::Matrix<T, D, D>;
  typename Sys::Linearisation lin;
  State ds;
  if (!sys.evaluate(t, s, ds, &lin)) return false;
  Aug a = Aug::Zero();
  double norm = 0.0;  // max row sum of |h·A|
  for (int i = 0; i < D; ++i) {
    for (int j = 0; j < D; ++j) a(i, j) = lin.jacobian(i, j);
    a(i, D) = lin.rate[i];
    double row = 0.0;
    for (int j = 0; j <= D; ++j) row += std::abs(value_of(a(i, j)));
    norm = std::max(norm, row * h);
  }
  if (!std::isfinite(norm)) return false;
  int levels = 0;
  while (norm > 0.25 && levels < 60) norm *= 0.5, ++levels;
  if (norm > 0.25) return false;
  const double tau = std::ldexp(h, -levels);
  Aug e1 = a, e2 = a;
  for (int i = 0; i <= D; ++i)
    for (int j = 0; j <= D; ++j) e1(i, j) *= tau, e2(i, j) *= tau * kSqrt2;
  e1 = small_expm(e1);  // exp(τA)
  e2 = small_expm(e2);  // exp(√2 τA)
  // 3-point rule on [0, 1] with nodes 0, c = √2 − 1, 1: exact for quadratics, weights > 0
  const double c = kSqrt2 - 1.0;
  const double w1 = 1.0 / (6.0 * c * (1.0 - c)), w2 = 0.5 - w1 * c, w0 = 1.0 - w1 - w2;
  Mat q = Mat::Zero();
  add_sandwich<D>(Aug(Aug::Identity()), lin.noise, 0.5 * tau, q);  // [0, τ] by the trapezoid
  add_sandwich<D>(e1, lin.noise, 0.5 * tau, q);
  Aug sq;
  double width = tau;
  for (int l = 0; l < levels; ++l) {  // [width, 2·width]
    add_sandwich<D>(e1, lin.noise, w0 * width, q);
    add_sandwich<D>(e2, lin.noise, w1 * width, q);
    small_product(e1, e1, sq), e1 = sq;
    small_product(e2, e2, sq), e2 = sq;
    add_sandwich<D>(e1, lin.noise, w2 * width, q);
    width *= 2.0;
  }
  // e1 = exp(hA): Φ and the mean's increment h φ₁(hF) b
  Mat p;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) p(i, j) = s[Pk::p(i, j)];
  for (int i = 0; i < D; ++i) s[i] += e1(i, D);
  for (int i = 0; i < D; ++i)
    for (int j = i; j < D; ++j) {
      T v = q(i, j) + q(j, i);
      v *= 0.5;
      for (int k = 0; k < D; ++k)
        for (int l = 0; l < D; ++l) v += e1(i, k) * p(k, l) * e1(j, l);
      s[Pk::p(i, j)] = v;
    }
  return true;
}

/// Substeps of the fallback per RK4 substep of the settings.
inline constexpr int kExponentialSubsteps = 4;

/// One sampling interval's time update: RK4 with `substeps`, retried with finer substeps from
/// the same state when a step leaves the model's domain, and where even the finest leaves it,
/// exponential_step's covariance-preserving substeps (substeps × kExponentialSubsteps). False
/// when every try failed.
template <int D, class Sys, class State>
bool propagate_interval(const Sys& sys, double t0, double dt, int substeps, State& s) {
  const State start = s;
  if (rk4_propagate(sys, t0, dt, substeps, s)) return true;
  for (const int finer : kSubstepRefinements) {
    s = start;
    if (rk4_propagate(sys, t0, dt, substeps * finer, s)) return true;
  }
  s = start;
  {
    // The measurement update's P_yy − P_xy²/S can round to ≤ 0 when x and y are almost fully
    // correlated (nearly deterministic motion): lift P_yy to the smallest value the x–y block
    // allows (its determinant ≥ 0), the rounding's size, before the exponential steps.
    using Pk = Packing<D>;
    auto& pyy = s[Pk::p(1, 1)];
    const auto& pxx = s[Pk::p(0, 0)];
    const auto& pxy = s[Pk::p(0, 1)];
    if (value_of(pxx) > 0.0 && !(value_of(pyy) * value_of(pxx) > value_of(pxy) * value_of(pxy))) {
      pyy = pxy * pxy / pxx;
      pyy *= 1.0 + 1e-9;
      pyy += kVarianceFloor;
    }
  }
  const int n = substeps * kExponentialSubsteps;
  const double h = dt / n;
  for (int i = 0; i < n; ++i)
    if (!exponential_step<D>(sys, t0 + i * h, h, s)) return false;
  return true;
}

/// Runs the filter over the block and returns Σ_k ℓ_k (k ≥ 1). `sink(k, e_k, S_k, ℓ_k,
/// filtered state)` is called for every scored sample after its update. On failure returns 0 with `fail` set.
template <class T, int D, class Sink>
T filter_block(const Structure& st, const Coefficients<T>& c, const BlockData& b,
               const FilterSettings& fs, Sink&& sink, FilterFailure& fail) {
  using std::log;
  using Pk = Packing<D>;
  using State = PackedState<T, D>;
  MomentSystem<T, D> sys(st, c);
  State s = State::Zero();
  s[0] = T(b.x[0]);
  s[Pk::p(0, 0)] = c.measurement_var;
  s[Pk::p(1, 1)] = T(b.y_prior_var);
  if constexpr (D == 4) {
    HiddenPrior<T> pr;
    if ((st.electro || st.colored) && hidden_prior(st, c, b.x[0], b.y_prior_var / b.v_prior_var, pr)) {
      // the stationary law of the linearised model given x_0 (hidden_prior.hpp)
      s[Pk::p(1, 1)] = pr.var_y;
      if (st.electro) s[2] = pr.mean_v, s[Pk::p(2, 2)] = pr.var_v, s[Pk::p(1, 2)] = pr.cov_yv;
      if (st.colored) s[3] = pr.mean_eta, s[Pk::p(3, 3)] = pr.var_eta, s[Pk::p(1, 3)] = pr.cov_yeta;
      if (st.electro && st.colored) s[Pk::p(2, 3)] = pr.cov_veta;
    } else {
      if (st.electro) s[Pk::p(2, 2)] = T(b.v_prior_var);
      if (st.colored) s[Pk::p(3, 3)] = c.intensity / (2.0 * c.tau);
    }
  }
  T total{};
  for (std::size_t k = 1; k < b.n; ++k) {
    const double t_prev = b.t0 + double(k - 1) * b.dt;
    sys.set_drive(t_prev, b.dt,
                  b.record_u ? input_cubic(b.record_u, b.record_n, b.first + k - 1, fs.input)
                             : InputCubic{});
    if (!propagate_interval<D>(sys, t_prev, b.dt, fs.substeps, s)) {
      fail = {true, k, "the moment equations left the model's domain (a22 < 0 or a variance <= 0) "
                       "under RK4 and under the covariance-preserving exponential steps"};
      return T{};
    }
    const T e = b.x[k] - s[0];
    const T S = s[Pk::p(0, 0)] + c.measurement_var;
    const double sv = value_of(S), ev = value_of(e);
    if (!(sv > 0.0) || !std::isfinite(sv) || !std::isfinite(ev)) {
      fail = {true, k, "the predicted variance of x is not finite and positive"};
      return T{};
    }
    const T ell = -0.5 * (kLog2Pi + log(S) + e * e / S);
    total += ell;
    // update: K = P_{·0}/S, m += K e, P −= P_{·0} P_{0·}/S
    T p0[D];
    for (int i = 0; i < D; ++i) p0[i] = s[Pk::p(i, 0)];
    const T inv_s = 1.0 / S;
    const T r_over_s = c.measurement_var * inv_s;  // P_0j − P_00 P_0j/S = P_0j·R/S, exactly ≥ 0
    for (int i = 0; i < D; ++i) {
      s[i] += p0[i] * inv_s * e;
      s[Pk::p(0, i)] = p0[i] * r_over_s;
      for (int j = std::max(i, 1); j < D; ++j) s[Pk::p(i, j)] -= p0[i] * p0[j] * inv_s;
    }
    sink(k, e, S, ell, s);
  }
  return total;
}

}  // namespace vehs::likelihood::detail

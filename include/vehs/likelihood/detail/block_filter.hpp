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
// leave the domain is redone with finer substeps; in a model with friction also one whose
// covariance the update could not keep valid, and where every count fails it is integrated by
// backward Euler steps, implicit_step.hpp), measurement update with
// x_k = x(t_k) + ε_k: innovation e_k = x_k − m_x, S_k = P_xx + σ_ε², log-likelihood
// −½(log 2πS_k + e_k²/S_k), Kalman gain P_{·x}/S_k.
#include <cmath>
#include <algorithm>
#include <cstddef>
#include <optional>

#include "vehs/likelihood/detail/hidden_prior.hpp"
#include "vehs/likelihood/detail/implicit_step.hpp"
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
/// pays; an interval that fails even at the finest is integrated by backward Euler
/// (kImplicitRefinement times the settings' count of steps).
inline constexpr int kSubstepRefinements[] = {4, 16, 64};
inline constexpr int kImplicitRefinement = 4;

/// Why a block fails when its moment equations leave the model's domain.
inline constexpr const char* kLeftDomain = "the moment equations left the model's domain (a22 < 0 or a variance <= 0)";

/// The intervals of an n-sample block that may take the backward-Euler fallback. A stiff spot
/// (friction as the axis sticks, a stop's wall) needs it on a few intervals; a model that needs it
/// along the record (a start whose moment equations blow up) is refused as diverged, at a bounded
/// cost, before its implicit steps cost hundreds of explicit ones on every interval.
inline std::size_t implicit_budget(std::size_t n) { return 8 + n / 32; }

/// Whether a packed state's covariance is one the measurement update keeps valid, with
/// measurement variance r: P_yy > 0, the other variances >= 0 and P_0j² < P_jj·(P_00 + r) for
/// every j (the updated variance P_jj − P_0j²/(P_00 + r) stays >= 0). RK4 steps beyond their
/// stability bound can end with |corr(x, y)| > 1 and positive variances; the update would then
/// turn P_yy negative.
template <class T, int D>
bool valid_covariance(const PackedState<T, D>& s, double r) {
  using Pk = Packing<D>;
  if (!(value_of(s[Pk::p(1, 1)]) > 0.0)) return false;
  double d[D];
  for (int i = 0; i < D; ++i) {
    d[i] = value_of(s[Pk::p(i, i)]);
    if (!(d[i] >= 0.0) || !std::isfinite(d[i])) return false;
  }
  for (int j = 1; j < D; ++j) {
    const double c = value_of(s[Pk::p(0, j)]);
    if (!(c * c <= d[j] * (d[0] + r) * (1.0 - 1e-12))) return false;
  }
  return true;
}

/// The RK4 substeps a block of n intervals may spend, retries included, as a multiple of
/// n × the settings' count, for a model with friction (beyond it the model is refused as
/// diverged). Friction on nearly deterministic motion retries about 2 intervals in 3 at 4× (3.7×
/// on average); a model that retries most intervals at 64× costs minutes per fit instead.
inline constexpr long long kSubstepWorkBudget = 10;

/// One sampling interval's time update: RK4 with `substeps`, retried with finer substeps from
/// the same state when a step leaves the model's domain or the covariance it ends with is not
/// valid. Adds the substeps spent to `work`. False when every try failed.
/// With `check` false (a model without friction) only the domain decides: the retries of
/// models whose moment equations are not stiff at a known velocity (hidden states, stops) cost
/// what they did before the check.
template <class T, int D, class Sys>
bool propagate_interval(const Sys& sys, double t0, double dt, int substeps, double r, PackedState<T, D>& s,
                        long long& work, bool check = true) {
  const PackedState<T, D> start = s;
  work += substeps;
  if (rk4_propagate(sys, t0, dt, substeps, s) && (!check || valid_covariance<T, D>(s, r))) return true;
  for (const int finer : kSubstepRefinements) {
    s = start;
    work += static_cast<long long>(substeps) * finer;
    if (rk4_propagate(sys, t0, dt, substeps * finer, s) && (!check || valid_covariance<T, D>(s, r))) return true;
  }
  return false;
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
  std::optional<ImplicitPropagator<T, D>> implicit;  // built at the first stiff interval
  std::size_t implicit_intervals = 0;
  long long work = 0;
  const long long work_budget = kSubstepWorkBudget * static_cast<long long>(b.n) * fs.substeps;
  for (std::size_t k = 1; k < b.n; ++k) {
    const double t_prev = b.t0 + double(k - 1) * b.dt;
    const InputCubic u =
        b.record_u ? input_cubic(b.record_u, b.record_n, b.first + k - 1, fs.input) : InputCubic{};
    sys.set_drive(t_prev, b.dt, u);
    const State start = s;
    const double r = value_of(c.measurement_var);
    const bool explicit_ok = propagate_interval<T, D>(sys, t_prev, b.dt, fs.substeps, r, s, work, st.friction);
    if (!explicit_ok && !st.friction) {
      fail = {true, k, kLeftDomain};
      return T{};
    }
    if (st.friction && work > work_budget) {
      fail = {true, k, "the moment equations needed finer RK4 steps on so many intervals that the filter's cost "
                       "bound (10 times the automatic substeps over the block) was reached (a model stiff along "
                       "most of the record)"};
      return T{};
    }
    if (!explicit_ok) {
      s = start;
      if (++implicit_intervals > implicit_budget(b.n)) {
        fail = {true, k, "the moment equations needed implicit steps on more intervals than the filter allows "
                         "(a model stiff or explosive along most of the record)"};
        return T{};
      }
      if (!implicit) implicit.emplace(st, c);
      if (!implicit->propagate(sys, t_prev, b.dt, kImplicitRefinement * fs.substeps, u, s) ||
          !valid_covariance<T, D>(s, r)) {
        fail = {true, k, kLeftDomain};
        return T{};
      }
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

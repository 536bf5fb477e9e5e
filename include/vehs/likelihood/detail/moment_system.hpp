#pragma once
// The moment equations of the assumed-density (Gaussian) filter's time update, generic over
// the scalar type T and the state dimension D (2: x, y; 4: x, y, v, η — an effect that is
// absent keeps its state at 0 with zero variance).
//
// For a Gaussian state s ~ N(m, P) (Särkkä & Sarmavuori 2013, continuous–discrete Gaussian
// filter; CTSM-R's EKF is its first-order special case):
//     dm/dt = E[f(s, t)]
//     dP/dt = E[∂f] P + P E[∂f]ᵀ + E[G Gᵀ]      (Stein: E[f (s − m)ᵀ] = E[∂f] P)
// where f is the drift of the state and G Gᵀ = diag(0, a22(x, y), 0, intensity/τ²). The
// expectations are exact under the Gaussian (gaussian_expectations.hpp): polynomial terms of
// any degree (E[x³] = m³ + 3mP_xx: the curvature an EKF drops), sign(y), y·|y| and the end
// stops' hinges (vehs/effects/impact_stop.hpp) in closed form — so the kinks of friction and stops are averaged over the
// state's spread instead of being linearised at the mean. The state is packed as
// [m_0 … m_{D−1}, P_00, P_01, …, P_0(D−1), P_11, …] (upper triangle by rows).
#include <cmath>

#include <Eigen/Core>

#include "vehs/likelihood/detail/flatten.hpp"
#include "vehs/likelihood/detail/gaussian_expectations.hpp"
#include "vehs/likelihood/detail/input_path.hpp"
#include "vehs/likelihood/detail/model_structure.hpp"
#include "vehs/likelihood/detail/scalar.hpp"
#include "vehs/likelihood/detail/user_expectation.hpp"

namespace vehs::likelihood::detail {

template <int D>
struct Packing {
  static constexpr int size = D + D * (D + 1) / 2;
  /// Index of P_ij (any order of i, j) in the packed state.
  static constexpr int p(int i, int j) {
    if (i > j) return p(j, i);
    return D + i * D - i * (i - 1) / 2 + (j - i);
  }
};

template <class T, int D>
using PackedState = Eigen::Matrix<T, Packing<D>::size, 1>;

/// Floor on variances inside square roots (keeps sqrt and its derivative finite at P = 0).
inline constexpr double kVarianceFloor = 1e-300;

template <class T, int D>
class MomentSystem {
 public:
  using Pk = Packing<D>;
  using State = PackedState<T, D>;

  MomentSystem(const Structure& st, const Coefficients<T>& c) : st_(st), c_(c) {}

  /// The drive over the current interval [t0, t0 + dt] (set per interval).
  void set_drive(double t0, double dt, const InputCubic& u) {
    t0_ = t0;
    inv_dt_ = 1.0 / dt;
    u_ = u;
  }

  /// ds/dt; false when E[a22] < 0 or a variance is not positive (outside the model's domain).
  VEHS_FLATTEN bool operator()(double t, const State& s, State& ds) const {
    using std::cos;
    using std::sqrt;
    const T& mx = s[0];
    const T& my = s[1];
    const T& pxx = s[Pk::p(0, 0)];
    const T& pxy = s[Pk::p(0, 1)];
    const T& pyy = s[Pk::p(1, 1)];
    if (!(value_of(pyy) > 0.0) || !(value_of(pxx) >= 0.0)) return false;
    T sx{}, sy{};
    if (st_.needs_sd) {
      sx = sqrt(pxx + kVarianceFloor);
      sy = sqrt(pyy);
    }
    moments_.compute(mx, my, pxx, pxy, pyy, st_.a_max_by_b, st_.max_py);
    const double u = eval_cubic(u_, (t - t0_) * inv_dt_);

    // E[b2] and E[∂b2] (the y row of E[∂f])
    T eb{}, gx{}, gy{};
    for (std::size_t j = 0; j < st_.drift.size(); ++j) {
      const Term& term = st_.drift[j];
      const T& c = c_.drift[j];
      switch (term.kind) {
        case TermKind::Monomial:
          eb += c * moments_(term.px, term.py);
          if (term.px > 0) gx += c * double(term.px) * moments_(term.px - 1, term.py);
          if (term.py > 0) gy += c * double(term.py) * moments_(term.px, term.py - 1);
          break;
        case TermKind::SignY:
          eb += c * expect_sign(my, sy);
          gy += c * expect_dsign(my, sy);
          break;
        case TermKind::YAbsY:
          eb += c * expect_y_abs_y(my, sy);
          gy += c * 2.0 * expect_abs(my, sy);
          break;
        case TermKind::Drive: eb += c * u; break;
        case TermKind::User: {
          const UserMoments<T> e = expect_user(term, mx, my, pxx, pxy, pyy, u);
          eb += c * e.value;
          gx += c * e.dx;
          gy += c * e.dy;
          break;
        }
      }
    }
    if (st_.impact) {
      const auto e = c_.stop.expectation(mx, sx);
      eb += e.force;
      gx += e.force_dx;
    }
    if (st_.harmonic) eb += c_.forcing.force(t);
    T gv{}, ge{};
    if constexpr (D == 4) {
      if (st_.electro) {
        eb -= c_.coupling * s[2];
        gv = -c_.coupling;
      }
      if (st_.colored) {
        eb += s[3];
        ge = T(1.0);
      }
    }
    // E[a22]
    T q{};
    for (std::size_t j = 0; j < st_.diffusion.size(); ++j) {
      const Term& term = st_.diffusion[j];
      if (term.kind == TermKind::Monomial)
        q += c_.diffusion[j] * moments_(term.px, term.py);
      else if (term.kind == TermKind::User)
        q += c_.diffusion[j] * expect_user(term, mx, my, pxx, pxy, pyy, u).value;
      else  // y·|y| (sign(y) and u are rejected by Structure::of)
        q += c_.diffusion[j] * expect_y_abs_y(my, sy);
    }
    if (!(value_of(q) >= 0.0)) return false;

    // means
    ds[0] = my;
    ds[1] = eb;
    // (FP)_ij by rows of F: row 0 = e_1, row 1 = (gx, gy, gv, ge), row 2 = (0, 1, −λ, 0),
    // row 3 = (0, 0, 0, −1/τ)
    auto P = [&](int i, int j) -> const T& { return s[Pk::p(i, j)]; };
    if constexpr (D == 2) {
      const T fp10 = gx * pxx + gy * pxy, fp11 = gx * pxy + gy * pyy;
      ds[Pk::p(0, 0)] = 2.0 * pxy;
      ds[Pk::p(0, 1)] = pyy + fp10;
      ds[Pk::p(1, 1)] = 2.0 * fp11 + q;
    } else {
      T inv_tau{};
      if (st_.colored) inv_tau = 1.0 / c_.tau;
      ds[2] = st_.electro ? T(my - c_.lambda * s[2]) : T(0.0);
      ds[3] = st_.colored ? T(-s[3] * inv_tau) : T(0.0);
      T fp[4][4];
      for (int j = 0; j < 4; ++j) {
        fp[0][j] = P(1, j);
        fp[1][j] = gx * P(0, j) + gy * P(1, j) + gv * P(2, j) + ge * P(3, j);
        fp[2][j] = st_.electro ? T(P(1, j) - c_.lambda * P(2, j)) : T(0.0);
        fp[3][j] = st_.colored ? T(-P(3, j) * inv_tau) : T(0.0);
      }
      for (int i = 0; i < 4; ++i)
        for (int j = i; j < 4; ++j) ds[Pk::p(i, j)] = fp[i][j] + fp[j][i];
      ds[Pk::p(1, 1)] += q;
      if (st_.colored) ds[Pk::p(3, 3)] += c_.intensity * inv_tau * inv_tau;
    }
    return true;
  }

 private:
  const Structure& st_;
  const Coefficients<T>& c_;
  mutable GaussianMoments<T> moments_;
  double t0_ = 0.0, inv_dt_ = 1.0;
  InputCubic u_{};
};

}  // namespace vehs::likelihood::detail

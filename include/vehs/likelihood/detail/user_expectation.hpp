#pragma once
// Expectations of a user's expression term g (vehs/core/user_function.hpp) under the filter's
// Gaussian state, generic over the scalar (double or ceres::Jet): E[g], E[∂x g], E[∂y g], which
// the moment equations need (moment_system.hpp). g is known only by its values, so:
//
// * g of one state variable z ~ N(m, s²) (x or y; u is known over the step): g is sampled on a
//   fixed grid of 129 points over m₀ ± 8 s₀ (spacing h = s₀/8) (m₀, s₀ the values of m, s;
//   straight stretches of a first pass at 4h are filled by their lines, so a feature narrower
//   than 4h that leaves no trace at that pass's points is not seen) and replaced by its
//   piecewise-linear interpolant, with each jump (an interval whose step dwarfs its neighbours')
//   located by bisection and kept as a step, and each kink (a slope change far larger than
//   around it) placed where the neighbouring lines meet. Exact for piecewise-linear g (friction
//   per direction, hinges, |y|); otherwise within h²/8·max|g″| (a feature much narrower than
//   the state's spread is averaged over the grid's spacing). The Gaussian integral of that interpolant is
//   written in closed form in (m, s) — Φ and φ of (z_k − m)/s — so its derivatives (the Jet's
//   slots, and E[g′] = ∂E[g]/∂m) are exact derivatives of the same smooth function: a friction
//   jump is averaged over the state's spread, as the catalogue's sign(y) is.
// * g of both x and y: a 12 × 12 Gauss–Hermite rule at (m₀, P₀) with importance weights
//   N(z; m, P)/N(z; m₀, P₀) (1 at the values, their derivatives carry the Jet's), and
//   E[∇g] = P⁻¹ E[g·(z − m)] (Stein). Exact for smooth g of low degree; a jump across both
//   variables is resolved only to the rule's spacing.
#include <array>
#include <cmath>

#include "vehs/core/terms.hpp"
#include "vehs/likelihood/detail/gaussian_expectations.hpp"
#include "vehs/likelihood/detail/scalar.hpp"

namespace vehs::likelihood::detail {

template <class T>
struct UserMoments {
  T value{}, dx{}, dy{};
};

namespace user_detail {

inline constexpr int kGrid = 128;      ///< intervals of the one-variable grid
inline constexpr double kSpan = 8.0;   ///< grid half-width in standard deviations

inline constexpr int kCoarse = 4;     ///< grid intervals per interval of the first, coarse pass

/// g on the grid z: first every kCoarse-th point; a coarse interval whose ends both have a second
/// difference at the rounding level of g (a straight stretch: the interpolation error is below
/// 1e-12·|g|) is filled by its line, any other sampled point by point. A step, a hinge or |y|
/// costs a few dozen evaluations instead of the grid's 129; a curved g all of them.
template <class G>
void sample(const G& at, const std::array<double, kGrid + 1>& z, std::array<double, kGrid + 1>& g) {
  constexpr int nc = kGrid / kCoarse;
  for (int i = 0; i <= nc; ++i) g[i * kCoarse] = at(z[i * kCoarse]);
  std::array<bool, nc + 1> bends{};
  for (int i = 1; i < nc; ++i) {
    const double a = g[(i - 1) * kCoarse], b = g[i * kCoarse], c = g[(i + 1) * kCoarse];
    bends[i] = std::abs(a - 2.0 * b + c) > 1e-12 * (std::abs(a) + 2.0 * std::abs(b) + std::abs(c));
  }
  bends[0] = bends[1];
  bends[nc] = bends[nc - 1];
  for (int i = 0; i < nc; ++i) {
    const int k0 = i * kCoarse;
    const bool straight = !bends[i] && !bends[i + 1];
    for (int j = 1; j < kCoarse; ++j)
      g[k0 + j] = straight ? g[k0] + (g[k0 + kCoarse] - g[k0]) * (double(j) / kCoarse) : at(z[k0 + j]);
  }
}

/// E[g(z)] and ∂/∂m of it for z ~ N(m, s²), g given by `at(z)` (double).
template <class T, class G>
void one_variable(const G& at, const T& m, const T& s, T& value, T& d_mean) {
  const double m0 = value_of(m), s0 = value_of(s);
  std::array<double, kGrid + 1> z{}, g{};
  for (int k = 0; k <= kGrid; ++k) z[k] = m0 + s0 * kSpan * (2.0 * k / kGrid - 1.0);
  sample(at, z, g);
  // the interpolant written as g(z) = g₀ + Σ a_j·(z − t_j)⁺ + Σ J_i·1{z > c_i} (constant beyond
  // the grid): its slope changes a_j and jumps J_i, collected segment by segment
  struct Knot {
    double at, slope_change, jump;
  };
  std::array<Knot, 2 * kGrid + 2> knots{};
  int n_knots = 0;
  double slope = 0.0, end = g[0], max_slope = 0.0;
  auto segment = [&](double a, double b, double ga, double gb) {
    const double sl = b > a ? (gb - ga) / (b - a) : slope;
    knots[n_knots++] = {a, sl - slope, ga - end};
    slope = sl;
    end = gb;
    max_slope = std::max(max_slope, std::abs(sl));
  };
  auto jump = [&](int k) {
    const double d = std::abs(g[k + 1] - g[k]);
    const double left = k > 0 ? std::abs(g[k] - g[k - 1]) : 0.0;
    const double right = k + 2 <= kGrid ? std::abs(g[k + 2] - g[k + 1]) : 0.0;
    if (!(d > 4.0 * std::max(left, right) && d > 1e-12 * (std::abs(g[k]) + std::abs(g[k + 1])))) return false;
    // a steep but smooth rise passes its middle value near the interval's midpoint; a step
    // keeps one end's value there
    const double gm = at(0.5 * (z[k] + z[k + 1]));
    return std::abs(gm - g[k]) < 1e-9 * d || std::abs(gm - g[k + 1]) < 1e-9 * d;
  };
  // a kink inside interval k (|y|, y·(y>0), a stop's hinge): the lines through the neighbouring
  // intervals meet inside it, and the slope changes far more there than around it
  auto kink = [&](int k, double& c, double& gc) {
    if (k < 2 || k + 3 > kGrid) return false;
    const double d0 = g[k - 1] - g[k - 2], d1 = g[k] - g[k - 1], d3 = g[k + 2] - g[k + 1], d4 = g[k + 3] - g[k + 2];
    const double bend = std::abs(d3 - d1), around = std::max(std::abs(d1 - d0), std::abs(d4 - d3));
    if (!(bend > 4.0 * around && bend > 1e-12 * (std::abs(d1) + std::abs(d3)))) return false;
    const double h = z[k] - z[k - 1], sl = d1 / h, sr = d3 / h;
    c = (g[k + 1] - g[k] + sl * z[k] - sr * z[k + 1]) / (sl - sr);  // g[k] + sl(c − z_k) = g[k+1] + sr(c − z_{k+1})
    gc = g[k] + sl * (c - z[k]);
    return c > z[k] && c < z[k + 1];
  };
  for (int k = 0; k < kGrid; ++k) {
    if (!jump(k)) {
      double c = 0.0, gc = 0.0;
      if (kink(k, c, gc)) {
        segment(z[k], c, g[k], gc);
        segment(c, z[k + 1], gc, g[k + 1]);
      } else {
        segment(z[k], z[k + 1], g[k], g[k + 1]);
      }
      continue;
    }
    // a step: locate where g crosses the middle of its two values, to 2⁻⁴⁰ of the interval
    // (a friction's or a stop's jump stays put from call to call: the thread's last location is
    // tried first and kept when the crossing lies within that precision of it)
    const double mid = 0.5 * (g[k] + g[k + 1]);
    const bool rising = g[k + 1] > g[k];
    const double precision = std::ldexp(z[k + 1] - z[k], -40);
    thread_local double last = 0.0;
    auto above = [&](double c) { return (at(c) > mid) == rising; };
    double c = last;
    if (!(c - precision > z[k] && c + precision < z[k + 1] && above(c + precision) && !above(c - precision))) {
      double lo = z[k], hi = z[k + 1];
      for (int it = 0; it < 40; ++it) {
        const double t = 0.5 * (lo + hi);
        (above(t) ? hi : lo) = t;
      }
      c = last = 0.5 * (lo + hi);
    }
    segment(z[k], c, g[k], g[k]);
    segment(c, z[k + 1], g[k + 1], g[k + 1]);
  }
  knots[n_knots++] = {z[kGrid], -slope, g[kGrid] - end};
  // E[(z − t)⁺] = s·φ(d) + (m − t)·Φ(d) and E[1{z > c}] = Φ(d), d = (m − t)/s; ∂/∂m: Φ(d), φ(d)/s.
  // Slope changes at the rounding level of a linear stretch are dropped: a step, a hinge or |y|
  // costs a few knots, not the grid's 129.
  const double negligible = 1e-10 * max_slope;
  value = T(g[0]);
  d_mean = T(0.0);
  for (int j = 0; j < n_knots; ++j) {
    const Knot& kn = knots[j];
    const bool bends = std::abs(kn.slope_change) > negligible, jumps = kn.jump != 0.0;
    if (!bends && !jumps) continue;
    const T d = (m - kn.at) / s;
    const T cdf = normal_cdf(d), pdf = normal_pdf(d);
    if (bends) {
      value += kn.slope_change * (s * pdf + (m - kn.at) * cdf);
      d_mean += kn.slope_change * cdf;
    }
    if (jumps) {
      value += kn.jump * cdf;
      d_mean += kn.jump * pdf / s;
    }
  }
}

/// Gauss–Hermite nodes and weights (probabilists', weights summing to 1) of order 12.
const std::array<double, 12>& hermite_nodes();
const std::array<double, 12>& hermite_weights();

}  // namespace user_detail

/// E[g], E[∂x g], E[∂y g] for (x, y) ~ N((mx, my), [[pxx, pxy], [pxy, pyy]]) at drive u.
template <class T>
UserMoments<T> expect_user(const Term& term, const T& mx, const T& my, const T& pxx, const T& pxy,
                           const T& pyy, double u) {
  using std::exp;
  using std::log;
  using std::sqrt;
  const UserFunction::Local f = term.fn->local();
  UserMoments<T> r;
  const double mx0 = value_of(mx), my0 = value_of(my);
  if (!term.fn->uses_x() || !term.fn->uses_y()) {
    if (term.fn->uses_y())
      user_detail::one_variable([&](double y) { return f(mx0, y, u); }, my, T(sqrt(pyy)), r.value, r.dy);
    else
      user_detail::one_variable([&](double x) { return f(x, my0, u); }, mx,
                                T(sqrt(pxx + 1e-300)), r.value, r.dx);
    return r;
  }
  // two variables: Gauss–Hermite at the values, importance-weighted
  const double a0 = value_of(pxx), b0 = value_of(pxy), c0 = value_of(pyy);
  const double l11 = std::sqrt(std::max(a0, 1e-300)), l21 = b0 / l11,
               l22 = std::sqrt(std::max(c0 - l21 * l21, 1e-300 * c0));
  const T det = pxx * pyy - pxy * pxy;
  const T ixx = pyy / det, ixy = -pxy / det, iyy = pxx / det;
  const double log_det0 = 2.0 * std::log(l11 * l22);
  const T half_log_ratio = 0.5 * (log_det0 - log(det));
  const auto& xi = user_detail::hermite_nodes();
  const auto& w = user_detail::hermite_weights();
  const double g0 = f(mx0, my0, u);  // centring: Σ w ξ = 0, less cancellation in E[g·(z − m)]
  T sg{}, sx{}, sy{};
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j) {
      const double zx = mx0 + l11 * xi[i], zy = my0 + l21 * xi[i] + l22 * xi[j];
      const double gv = f(zx, zy, u) - g0;
      const T dx = zx - mx, dy = zy - my;
      const T q = dx * dx * ixx + 2.0 * dx * dy * ixy + dy * dy * iyy;
      const T ratio = exp(half_log_ratio - 0.5 * q + 0.5 * (xi[i] * xi[i] + xi[j] * xi[j]));
      const T wg = (w[i] * w[j] * gv) * ratio;
      sg += wg;
      sx += wg * dx;
      sy += wg * dy;
    }
  r.value = sg + g0;
  r.dx = ixx * sx + ixy * sy;
  r.dy = ixy * sx + iyy * sy;
  return r;
}

}  // namespace vehs::likelihood::detail

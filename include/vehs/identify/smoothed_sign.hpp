#pragma once
// What the ULI acceleration sees of Coulomb friction: the smoothed sign S(v̂) and its derivatives.
//
// A sensor samples a continuous process; central kinematics at stride h give
//   â = (1/h²) ∫_{−h}^{h} (h − |u|) ẍ(t+u) du   (the tent average of ẍ),
//   v̂ = (1/2h) ∫_{−h}^{h} y(t+u) du             (the window average of y).
// So of a friction force −μ sign(y) the target â holds −μ·tentavg sign(y(t+u)), not −μ sign(v̂).
// Over the window y(t+u) = y(t−h) + σ(B(u) − B(−h)) + O(h) (σ² = a22(x), B a Brownian motion),
// hence y(t+u) − v̂ = σ(B(u) − B̄) + O(h): Gaussian, independent of y(t−h), with variance
// a22·τ(u), τ(u) = Var(B(u) − B̄) = h/6 + u²/(2h) (for W from 0 over [0, T]: Var(W(t) − W̄) =
// t²/T − t + T/3, T = 2h, t = u + h). The density of y(t−h) is flat on the scale σ√h, so given v̂
// the variable y(t+u) − v̂ keeps that distribution and E[sign(y(t+u)) | v̂] = erf(v̂/√(2a22·τ(u))).
// The tent average, with u = hs:
//   S(v̂) = E[tentavg sign(y) | v̂] = 2 ∫₀¹ (1 − s) erf(v̂ / w(s)) ds,   w(s)² = a22·h·(s² + 1/3) + 2e,
// e the variance of white sensor noise in v̂ (noisy estimator; 0 otherwise). Regressing â on S
// instead of sign(v̂) leaves a misfit −μ(tentavg sign(y) − S(v̂)) orthogonal to any function of
// v̂; with sign(v̂) the misfit −μ(S − sign)(v̂) is not: E[sign(v̂)(S − sign)(v̂)] = −∫p(v)(1 − |S(v)|)dv
// ≈ −(4/√π)·0.348·p_v̂(0)·√(a22·h) ≈ −0.785·p_v̂(0)·√(a22 h) — about −1 % of E[sign²] on the
// paper's model at h = 0.005, which the strong correlation of sign(y) with y (≈ 0.8) turned into
// μ −5.5 % and β +10 % (50 seeds: tests/identify/test_bias_study.cpp). The Itô correction of the
// column is ½a22·E[S'(v̂)] (Stein's lemma: the noise of â and of v̂ are jointly Gaussian given the
// past, covariance a22/2), S' a smooth kernel of integral 2 in place of 2δ(v) — to first order.
// The friction itself pulls y towards 0 inside the window, which changes the covariance of v̂
// with the noise of â exactly where S' lives (|v̂| ≲ σ√h), by a relative O(μ√(h/a22)) — a few %
// of a term larger than the friction signal itself (½a22·E[S'] ≈ 1.3 μ on the paper's model).
// Malliavin calculus: with ξ = σ∫k(s)dW(s), k(s) = (h − |s|)/h², E[ξ S(v̂)] = E[S'(v̂)·σ∫k(s)D_s v̂ ds]
// and D_s y(r) = σ·1{s < r}·(1 + ∫_s^r ∂_y b2 du), ∂_y b2 ∋ −2μ δ(y): so
//   σ∫k D_s v̂ ds = a22/2 − μ·a22 ∫_{−h}^{h} δ(y(u)) ω(u) du,   ω(u) = (h − u)·K(u)/h,
// K(u) = ∫_{−h}^{u} k(s) ds. Averaged over the (flat) position of the window's velocity, with
// y(u) − v̂ ~ N(0, a22 τ(u)) as above: E[ξ S] = E[½a22 S'(v̂)(1 − μQ)], Q = q₀·√(h/a22),
//   q₀ = ∫_{−1}^{1} (1 − t) κ(t) (4/√π) ∫₀¹ (1 − s)(s² + t² + 2/3)^{−1/2} ds dt = 0.673502
// (κ(t) = K(ht): the tent's distribution function). With c = −μ the coefficient of the column,
// the sign row of the normal equations gains c·Σ ½a22 S' Q on its diagonal (sign_ito_response).
// Measured on the same 50 seeds (paper model, μ = 0.05, h = 0.005; test_bias_study.cpp): μ
// −5.5 % ± 0.7 % with sign(v̂), +3.1 % ± 0.7 % with S but without the response term, −1.4 % ± 0.7 %
// with both (β: +9.7 %, −4.9 %, +2.8 % ± 1.7 %).
// Neglected: the drift's own change of y over the window (b·u, odd in u, cancels in the tent
// average to first order; second order ≈ b²h/a22 of the correction, i.e. ≲ 0.3 % of μ here) and
// the variation of a22 and of the density of y over a velocity range σ√h.
#include <cmath>

namespace vehs::identify {

/// S(v), S'(v), S''(v) for the width function w(s)² = c·(s² + 1/3) + d (c = a22·h, d = 2e).
struct SmoothedSign {
  double value = 0.0, d1 = 0.0, d2 = 0.0;
};

/// q₀ of the friction's response term (header comment).
inline constexpr double kSignResponse = 0.6735022;

inline SmoothedSign smoothed_sign(double v, double c, double d) {
  // 8-point Gauss–Legendre on [0, 1] (the integrand is smooth in s: w(s) ≥ w(0) > 0)
  static constexpr double kNode[8] = {0.019855071751231856, 0.10166676129318664, 0.2372337950418355,
                                      0.4082826787521751,  0.5917173212478249,  0.7627662049581645,
                                      0.8983332387068134,  0.9801449282487681};
  static constexpr double kWeight[8] = {0.05061426814518813, 0.11119051722668724, 0.15685332293894363,
                                        0.18134189168918100, 0.18134189168918100, 0.15685332293894363,
                                        0.11119051722668724, 0.05061426814518813};
  SmoothedSign r;
  const double wmax2 = c * (1.0 + 1.0 / 3.0) + d;
  if (v * v > 64.0 * wmax2) {  // erf(8) = 1 − 1e-29: the plain sign
    r.value = static_cast<double>((v > 0) - (v < 0));
    return r;
  }
  const double k = 2.0 / std::sqrt(M_PI);
  for (int i = 0; i < 8; ++i) {
    const double s = kNode[i], wt = 2.0 * kWeight[i] * (1.0 - s);
    const double w2 = c * (s * s + 1.0 / 3.0) + d, w = std::sqrt(w2);
    const double g = k * std::exp(-v * v / w2) / w;  // d/dv erf(v/w)
    r.value += wt * std::erf(v / w);
    r.d1 += wt * g;
    r.d2 += wt * g * (-2.0 * v / w2);
  }
  return r;
}

}  // namespace vehs::identify

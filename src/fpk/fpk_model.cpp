// FpkModel: the drift and diffusion of the stationary FPK, with the checks that a stationary
// 2-D density exists; model parameters by name for sweeps.
#include <algorithm>
#include <cmath>
#include <limits>

#include "vehs/core/detail/format.hpp"
#include "vehs/core/diffusion_domain.hpp"
#include "vehs/core/error.hpp"
#include "vehs/effects/from_model.hpp"
#include "vehs/fpk/fpk_model.hpp"

namespace vehs::fpk {

namespace {

std::string num(double v) { return vehs::detail::format_number(v, 6); }

}  // namespace

FpkModel::FpkModel(const Model& model, const std::string& where) : model_(model), where_(where) {
  validate_model(model_, where_);
  // simulate-vehs's and diagnose-vehs's rule (global; a22 >= 0 on the grid is checked as assembled)
  if (auto why = diffusion_negative_at_large_x(model_); !why.empty()) throw Error(where_ + ": " + why);
  for (const auto& tc : model_.drift) {
    if (tc.term.depends_on_u() && tc.coef != 0.0)
      throw Error(where_ + ": drift term 'u' (a recorded drive) makes the process time-dependent; "
                           "a stationary Fokker-Planck density does not exist; for its mean power run simulate-vehs "
                           "with the recorded input as 'drive' and 'statistics' (docs/outputs.md, Mean power)");
    if (tc.term.kind == TermKind::SignY && tc.coef != 0.0) has_sign_y_ = true;
  }
  for (const auto& e : model_.effects) {
    switch (e.id) {
      case EffectId::ImpactStop:
        has_stop_ = true;
        stop_ = effects::from_effect<effects::ImpactStop>(e);
        break;
      case EffectId::HarmonicForcing:
        throw Error(where_ + ": effect 'harmonic_forcing' makes the process time-dependent "
                             "(periodic, not stationary); no stationary 2-D Fokker-Planck density");
      case EffectId::ElectromechanicalCoupling:
        throw Error(where_ + ": effect 'electromechanical_coupling' adds a hidden state v, so "
                             "(X, Y) alone is not Markov; no stationary 2-D Fokker-Planck density");
      case EffectId::ColoredNoise:
        throw Error(where_ + ": effect 'colored_noise' adds a hidden noise state, so (X, Y) alone "
                             "is not Markov; no stationary 2-D Fokker-Planck density");
      default:
        throw Error(where_ + ": effect '" + e.name() + "' is not supported by the FPK solver");
    }
  }
  // Noise must be present somewhere.
  bool any_noise = false;
  for (const auto& tc : model_.diffusion) any_noise = any_noise || tc.coef != 0.0;
  require(any_noise, where_ + ": diffusion is zero: without noise the stationary density is a "
                              "point mass, not a function on a grid");
  // Confinement: the x-only restoring force U'(x) = −Σ c·x^px (py = 0) (+ stops) must
  // point back to the origin for |x| → ∞ on both sides.
  int degree = -1;
  double lead = 0.0;
  for (const auto& tc : model_.drift)
    if (tc.term.kind == TermKind::Monomial && tc.term.py == 0 && tc.coef != 0.0 &&
        tc.term.px > degree) {
      degree = tc.term.px;
      lead = -tc.coef;
    }
  if (degree >= 2) {
    if (degree % 2 == 0)
      throw Error(where_ + ": the potential does not confine: the leading restoring-force term x^" +
                  std::to_string(degree) +
                  " is even, so U(x) → −∞ on one side and no stationary density exists");
    if (lead <= 0.0)
      throw Error(where_ + ": the potential does not confine: the leading restoring force " +
                  num(lead) + "·x^" + std::to_string(degree) +
                  " pushes outwards (drift['x^" + std::to_string(degree) +
                  "'] must be negative)");
  } else {
    const double slope = (degree == 1 ? lead : 0.0) + (has_stop_ ? stop_.stiffness() : 0.0);
    if (!(slope > 0.0))
      throw Error(where_ + ": the potential does not confine: the restoring force grows at most "
                           "like " + num(slope) +
                  "·x for large |x| (need a positive stiffness, an odd leading power with a "
                  "negative drift coefficient, or an impact_stop)");
  }
  // Dissipation: some y-dependent drift term is needed.
  bool any_y = false;
  for (const auto& tc : model_.drift) any_y = any_y || (tc.term.depends_on_y() && tc.coef != 0.0);
  require(any_y, where_ + ": the drift has no velocity-dependent (damping) term: the energy grows "
                          "without bound and no stationary density exists");
}

double FpkModel::b2(double x, double y) const {
  double v = model_.b2(x, y);
  if (has_stop_) v += stop_.force(x);
  return v;
}

double FpkModel::db2_dy(double x, double y) const {
  double v = 0.0;
  for (const auto& tc : model_.drift) v += tc.coef * tc.term.d_dy(x, y);
  return v;
}

double FpkModel::a22(double x, double y) const { return model_.a22(x, y); }

double FpkModel::da22_dy(double x, double y) const {
  double v = 0.0;
  for (const auto& tc : model_.diffusion) v += tc.coef * tc.term.d_dy(x, y);
  return v;
}

double FpkModel::d2a22_dy2(double x, double y) const {
  double v = 0.0;
  for (const auto& tc : model_.diffusion) v += tc.coef * tc.term.d2_dy2(x, y);
  return v;
}

double FpkModel::restoring_force(double x) const { return -b2(x, 0.0); }

double FpkModel::potential(double x) const {
  double u = 0.0;
  for (const auto& tc : model_.drift)
    if (tc.term.kind == TermKind::Monomial && tc.term.py == 0)
      u -= tc.coef * ipow(x, tc.term.px + 1) / (tc.term.px + 1);
  if (has_stop_) u += stop_.potential(x);
  return u;
}

double FpkModel::damping(double x, double v) const {
  return -(b2(x, v) - b2(x, -v)) / (2.0 * v);
}

double FpkModel::temperature(double x) const {
  const double a = a22(x, 0.0);
  if (!(a > 0.0)) return 0.0;
  double v = 1.0;
  double t = 0.0;
  for (int it = 0; it < 200; ++it) {
    const double beta = damping(x, std::max(v, 1e-12));
    if (!(beta > 0.0))
      throw Error(where_ + ": no dissipation at x = " + num(x) + ", |y| ≈ " + num(v) +
                  ": the effective damping −(b2(x,v) − b2(x,−v))/(2v) = " + num(beta) +
                  " is not positive, so no stationary density exists");
    t = a / (2.0 * beta);
    const double v_new = std::sqrt(v * std::sqrt(t));  // damped fixed-point step
    if (std::abs(v_new - v) <= 1e-10 * v) break;
    v = v_new;
  }
  return t;
}

}  // namespace vehs::fpk

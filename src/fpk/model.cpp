// FpkModel: the drift and diffusion of the stationary FPK, with the checks that a stationary
// 2-D density exists; model parameters by name for sweeps.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "vehs/core/error.hpp"
#include "vehs/fpk/stationary.hpp"

namespace vehs::fpk {

namespace {

std::string num(double v) {
  std::ostringstream os;
  os.precision(6);
  os << v;
  return os.str();
}

}  // namespace

FpkModel::FpkModel(const Model& model, const std::string& where) : model_(model), where_(where) {
  validate_model(model_, where_);
  for (const auto& tc : model_.drift) {
    if (tc.term.depends_on_u() && tc.coef != 0.0)
      throw Error(where_ + ": drift term 'u' (a recorded drive) makes the process time-dependent; "
                           "a stationary Fokker-Planck density does not exist");
    if (tc.term.kind == TermKind::SignY && tc.coef != 0.0) has_sign_y_ = true;
  }
  for (const auto& e : model_.effects) {
    switch (e.id) {
      case EffectId::ImpactStop:
        has_stop_ = true;
        k_stop_ = e.param("k_stop");
        gap_ = e.param("gap");
        gap_neg_ = e.params.count("gap_neg") ? e.param("gap_neg") : gap_;
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
    const double slope = (degree == 1 ? lead : 0.0) + (has_stop_ ? k_stop_ : 0.0);
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
  if (has_stop_) {
    if (x > gap_) v -= k_stop_ * (x - gap_);
    if (x < -gap_neg_) v -= k_stop_ * (x + gap_neg_);
  }
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
  if (has_stop_) {
    if (x > gap_) u += 0.5 * k_stop_ * (x - gap_) * (x - gap_);
    if (x < -gap_neg_) u += 0.5 * k_stop_ * (x + gap_neg_) * (x + gap_neg_);
  }
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

// ---- parameters by name ---------------------------------------------------------------------

namespace {

struct TermParam {
  bool drift = true;
  Term term;
  double sign = 1.0;  ///< parameter = sign · coefficient
};

bool parse_term_param(const std::string& name, TermParam& out) {
  auto term_in = [&](const std::string& prefix, bool drift) {
    if (name.size() > prefix.size() + 1 && name.compare(0, prefix.size() + 1, prefix + "[") == 0 &&
        name.back() == ']') {
      out.drift = drift;
      out.term = Term::parse(name.substr(prefix.size() + 1, name.size() - prefix.size() - 2));
      out.sign = 1.0;
      return true;
    }
    return false;
  };
  if (term_in("drift", true) || term_in("diffusion", false)) return true;
  if (name == "beta") {
    out = {true, Term::monomial(0, 1), -1.0};
    return true;
  }
  if (name == "2D" || name == "D") {
    out = {false, Term::monomial(0, 0), name == "D" ? 0.5 : 1.0};
    return true;
  }
  if (name == "2Q" || name == "Q") {
    out = {false, Term::monomial(2, 0), name == "Q" ? 0.5 : 1.0};
    return true;
  }
  if (name.size() >= 2 && name[0] == 'k' &&
      name.find_first_not_of("0123456789", 1) == std::string::npos && name.size() <= 3) {
    out = {true, Term::monomial(std::stoi(name.substr(1)), 0), -1.0};
    return true;
  }
  return false;
}

const char* kParamHelp =
    " (known: beta, k<i>, 2D, 2Q, D, Q, drift[<term>], diffusion[<term>], impact_stop.<param>)";

}  // namespace

void set_model_parameter(Model& model, const std::string& name, double value) {
  require(std::isfinite(value), "sweep parameter '" + name + "' must be finite");
  TermParam tp;
  if (parse_term_param(name, tp)) {
    TermList& list = tp.drift ? model.drift : model.diffusion;
    const double coef = value / tp.sign;
    for (auto& tc : list)
      if (tc.term == tp.term) {
        tc.coef = coef;
        return;
      }
    list.push_back({tp.term, coef});
    canonicalize(list, "sweep");
    return;
  }
  const auto dot = name.find('.');
  if (dot != std::string::npos) {
    const EffectId id = enum_from_string(kEffectNames, name.substr(0, dot), "sweep parameter '" + name + "'");
    const std::string key = name.substr(dot + 1);
    for (auto& e : model.effects)
      if (e.id == id) {
        require(e.params.count(key) > 0, "sweep parameter '" + name + "': effect '" + e.name() +
                                             "' has no parameter '" + key + "'");
        e.params[key] = value;
        return;
      }
    throw Error("sweep parameter '" + name + "': the model has no effect '" + name.substr(0, dot) + "'");
  }
  throw Error("unknown sweep parameter '" + name + "'" + kParamHelp);
}

double get_model_parameter(const Model& model, const std::string& name) {
  TermParam tp;
  if (parse_term_param(name, tp))
    return tp.sign * coefficient(tp.drift ? model.drift : model.diffusion, tp.term);
  const auto dot = name.find('.');
  if (dot != std::string::npos) {
    const EffectId id = enum_from_string(kEffectNames, name.substr(0, dot), "parameter '" + name + "'");
    if (const Effect* e = model.find_effect(id)) return e->param(name.substr(dot + 1));
    throw Error("parameter '" + name + "': the model has no effect '" + name.substr(0, dot) + "'");
  }
  throw Error("unknown parameter '" + name + "'" + kParamHelp);
}

}  // namespace vehs::fpk

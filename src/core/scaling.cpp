#include "vehs/core/scaling.hpp"

#include <algorithm>
#include <cmath>

#include "vehs/core/error.hpp"
#include "vehs/effects/from_model.hpp"
#include "vehs/effects/harmonic_forcing.hpp"
#include "vehs/effects/impact_stop.hpp"

namespace vehs {

namespace {

bool positive_finite(double v) { return std::isfinite(v) && v > 0.0; }

/// The power of ten nearest to `v` in log; 1 for 0 or a non-finite figure.
double power_of_ten_near(double v) {
  if (!positive_finite(v)) return 1.0;
  return std::pow(10.0, std::round(std::log10(v)));
}

/// A user term's typical size at the scales: the largest |g| of its physical expression over the
/// states (±L, ±L/T, ±U), to the nearest power of ten (1 where g vanishes there). Its internal
/// values are g/size, O(1) like the other terms' (a hardening spring "-x^3" in metres is 1e-9:
/// its standard error came out "not positive" from the score covariance's round-off).
double user_term_size(const Term& t, const Scales& s) {
  // the physical expression g(X) = fn(X / scales) / value factor, whatever units t is in
  const UserFunction& f = *t.fn;
  const auto& k = f.scales();
  double size = 0.0;
  for (int c = 0; c < 8; ++c) {
    const double v = std::abs(f((c & 1 ? -1.0 : 1.0) * s.length / k[0], (c & 2 ? -1.0 : 1.0) * s.length / s.time / k[1],
                                (c & 4 ? -1.0 : 1.0) * s.input / k[2]) /
                              f.value_factor());
    if (std::isfinite(v)) size = std::max(size, v);
  }
  return power_of_ten_near(size);
}

/// Physical value of one internal unit of the term's own value.
double term_scale(const Term& t, const Scales& s) {
  const double v = s.length / s.time;
  switch (t.kind) {
    case TermKind::Monomial: return std::pow(s.length, t.px) * std::pow(v, t.py);
    case TermKind::SignY: return 1.0;
    case TermKind::YAbsY: return v * v;
    case TermKind::Drive: return s.input;
    case TermKind::User: return user_term_size(t, s);  // and its function rescaled (rescale_user_terms)
  }
  return 1.0;
}

/// User terms evaluated at the other units' state over their size: g(L^−power·x, …)·size^power.
void rescale_user_terms(TermList& terms, const Scales& s, int power) {
  const double kx = std::pow(s.length, -power), ky = std::pow(s.length / s.time, -power),
               ku = std::pow(s.input, -power);
  for (auto& tc : terms)
    if (tc.term.is_user()) tc.term = rescaled(tc.term, kx, ky, ku, std::pow(user_term_size(tc.term, s), power));
}

double acceleration(const Scales& s) { return s.length / (s.time * s.time); }
double variance_rate(const Scales& s) { return s.length * s.length / (s.time * s.time * s.time); }

/// The scale of a covariance name ("drift[x^3]", "diffusion[1]", "<effect>.<param>").
double parameter_scale(const std::string& name, const Scales& s) {
  auto inner = [&](std::size_t open) { return name.substr(open, name.size() - open - 1); };
  if (name.rfind("drift[", 0) == 0 && name.back() == ']')
    return drift_coefficient_scale(Term::parse(inner(6)), s);
  if (name.rfind("diffusion[", 0) == 0 && name.back() == ']')
    return diffusion_coefficient_scale(Term::parse(inner(10)), s);
  const auto dot = name.find('.');
  if (dot != std::string::npos) {
    const std::string effect = name.substr(0, dot);
    for (const auto& spec : effect_catalogue())
      if (spec.name == effect) return effect_parameter_scale(spec.id, name.substr(dot + 1), s);
  }
  throw Error("covariance: unknown parameter name '" + name +
              "' (expected drift[<term>], diffusion[<term>] or <effect>.<param>)");
}

void scale_terms(TermList& terms, std::map<std::string, double>& errors, double (*scale)(const Term&, const Scales&),
                 const Scales& s, int power) {
  for (auto& tc : terms) {
    const double f = std::pow(scale(tc.term, s), power);
    tc.coef *= f;
    auto it = errors.find(tc.term.name());
    if (it != errors.end()) it->second *= f;
  }
}

std::vector<Term> terms_to_internal(std::vector<Term> terms, const Scales& s) {
  for (auto& t : terms)
    if (t.is_user()) t = rescaled(t, s.length, s.length / s.time, s.input, 1.0 / user_term_size(t, s));
  return terms;
}

Model convert(const Model& in, const Scales& s, int power) {
  if (auto why = s.invalid_reason(); !why.empty()) throw Error("scales: " + why);
  Model m = in;
  scale_terms(m.drift, m.drift_stderr, drift_coefficient_scale, s, power);
  scale_terms(m.diffusion, m.diffusion_stderr, diffusion_coefficient_scale, s, power);
  rescale_user_terms(m.drift, s, power);
  rescale_user_terms(m.diffusion, s, power);
  for (auto& e : m.effects) e = scale_effect(e, s, power);
  if (!m.covariance.empty()) {
    std::vector<double> f(m.covariance.size());
    for (std::size_t i = 0; i < f.size(); ++i)
      f[i] = std::pow(parameter_scale(m.covariance.names[i], s), power);
    for (std::size_t i = 0; i < f.size(); ++i)
      for (std::size_t j = 0; j < f.size(); ++j) m.covariance(i, j) *= f[i] * f[j];
  }
  if (m.fit) {
    m.fit->sampling.dt *= std::pow(s.time, power);
    m.fit->sampling.sensor_noise_sd *= std::pow(s.length, power);
    m.fit->sampling.quantisation_step *= std::pow(s.length, power);
  }
  return m;
}

}  // namespace

std::string Scales::invalid_reason() const {
  if (!positive_finite(length)) return "the length scale must be finite and > 0";
  if (!positive_finite(time)) return "the time scale must be finite and > 0";
  if (!positive_finite(input)) return "the input scale must be finite and > 0";
  return "";
}

Scales natural_scales(const Dataset& data) {
  double xx = 0.0, vv = 0.0, uu = 0.0;
  double nx = 0.0, nv = 0.0;
  for (const auto& r : data.records) {
    const double* x = data.x_of(r);
    double mean = 0.0;
    for (std::size_t i = 0; i < r.size; ++i) mean += x[i];
    mean /= static_cast<double>(std::max<std::size_t>(r.size, 1));
    for (std::size_t i = 0; i < r.size; ++i) xx += (x[i] - mean) * (x[i] - mean);
    nx += static_cast<double>(r.size);
    if (r.dt > 0.0)
      for (std::size_t i = 1; i < r.size; ++i) {
        const double v = (x[i] - x[i - 1]) / r.dt;
        vv += v * v;
        nv += 1.0;
      }
    if (const double* u = data.u_of(r))
      for (std::size_t i = 0; i < r.size; ++i) uu += u[i] * u[i];
  }
  Scales s;
  if (nx > 0.0) s.length = power_of_ten_near(std::sqrt(xx / nx));
  if (nv > 0.0 && xx > 0.0 && vv > 0.0) s.time = power_of_ten_near(std::sqrt((xx / nx) / (vv / nv)));
  if (nx > 0.0 && data.has_u()) s.input = power_of_ten_near(std::sqrt(uu / nx));
  return s;
}

double drift_coefficient_scale(const Term& term, const Scales& s) {
  return acceleration(s) / term_scale(term, s);
}

double diffusion_coefficient_scale(const Term& term, const Scales& s) {
  return variance_rate(s) / term_scale(term, s);
}

double effect_parameter_scale(EffectId effect, std::string_view p, const Scales& s) {
  const double L = s.length, T = s.time;
  switch (effect) {
    case EffectId::AsymmetricStiffness:  // k<n>: coefficient of x^n in the force
      if (p.size() >= 2 && p[0] == 'k') return drift_coefficient_scale(Term::monomial(std::stoi(std::string(p.substr(1)))), s);
      break;
    case EffectId::CoulombFriction: return acceleration(s);
    case EffectId::QuadraticDamping: return drift_coefficient_scale(Term::y_abs_y(), s);
    case EffectId::NonlinearDamping:
      if (p == "c_x2y") return drift_coefficient_scale(Term::monomial(2, 1), s);
      if (p == "c_y3") return drift_coefficient_scale(Term::monomial(0, 3), s);
      break;
    case EffectId::ImpactStop: return effects::unit_scale_of<effects::ImpactStop>(p, L, T);
    case EffectId::HarmonicForcing: return effects::unit_scale_of<effects::HarmonicForcing>(p, L, T);
    case EffectId::ElectromechanicalCoupling: return p == "lambda" ? 1.0 / T : 1.0 / (T * T);
    case EffectId::ColoredNoise: return p == "tau" ? T : variance_rate(s);
    case EffectId::VelocityDependentNoise: return diffusion_coefficient_scale(Term::monomial(0, 2), s);
  }
  throw Error("scales: effect '" + enum_to_string(kEffectNames, effect) + "' has no parameter '" +
              std::string(p) + "'");
}

Effect scale_effect(const Effect& effect, const Scales& s, int power) {
  Effect e = effect;
  for (auto& [k, v] : e.params) v *= std::pow(effect_parameter_scale(e.id, k, s), power);
  for (auto& [k, v] : e.stderr_) v *= std::pow(effect_parameter_scale(e.id, k, s), power);
  return e;
}

Dataset to_internal(const Dataset& data, const Scales& s) {
  if (auto why = s.invalid_reason(); !why.empty()) throw Error("scales: " + why);
  Dataset d;
  d.records = data.records;
  for (auto& r : d.records) {
    r.t0 /= s.time;
    r.dt /= s.time;
  }
  auto scaled = [](const Column& v, double by) {
    std::vector<double> out(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) out[i] = v[i] / by;
    return out;
  };
  d.x = scaled(data.x, s.length);
  d.u = scaled(data.u, s.input);
  d.y = scaled(data.y, s.length / s.time);
  return d;
}

Model to_physical(const Model& internal, const Scales& s) { return convert(internal, s, +1); }
Model to_internal(const Model& physical, const Scales& s) { return convert(physical, s, -1); }

std::vector<Term> to_internal(std::vector<Term> terms, const Scales& s) { return terms_to_internal(std::move(terms), s); }

}  // namespace vehs

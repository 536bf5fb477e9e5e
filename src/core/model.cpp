#include "vehs/core/model.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "vehs/core/error.hpp"
#include "vehs/effects/from_model.hpp"
#include "vehs/effects/harmonic_forcing.hpp"
#include "vehs/effects/impact_stop.hpp"

namespace vehs {

namespace {
constexpr double kFree = -std::numeric_limits<double>::infinity();
}

const std::vector<EffectSpec>& effect_catalogue() {
  static const std::vector<EffectSpec> catalogue = {
      {EffectId::AsymmetricStiffness, "asymmetric_stiffness",
       "restoring force gains even powers: −(k0 + k2·x² + k4·x⁴ + …)", true,
       {{"k0", "constant force (tilt) coefficient", kFree, false, 0.0},
        {"k2", "coefficient of x² in U'(x)", kFree, false, 0.0},
        {"k4", "coefficient of x⁴ in U'(x)", kFree, false, 0.0},
        {"k6", "coefficient of x⁶ in U'(x)", kFree, false, 0.0},
        {"k8", "coefficient of x⁸ in U'(x)", kFree, false, 0.0}}},
      {EffectId::CoulombFriction, "coulomb_friction", "dry friction force −mu·sign(y)", true,
       {{"mu", "friction force level", 0.0, false, std::nullopt}}},
      {EffectId::QuadraticDamping, "quadratic_damping", "air drag −c·y·|y|", true,
       {{"c", "quadratic damping coefficient", 0.0, false, std::nullopt}}},
      {EffectId::NonlinearDamping, "nonlinear_damping",
       "amplitude-dependent damping −c_x2y·x²·y − c_y3·y³", true,
       {{"c_x2y", "coefficient of x²·y", kFree, false, 0.0},
        {"c_y3", "coefficient of y³", kFree, false, 0.0}}},
      effects::spec_of<effects::ImpactStop>(EffectId::ImpactStop),
      effects::spec_of<effects::HarmonicForcing>(EffectId::HarmonicForcing),
      {EffectId::ElectromechanicalCoupling, "electromechanical_coupling",
       "hidden state dv = (y − lambda·v) dt feeding back the force −coupling·v "
       "(coupling = θ·κ of dv = (κ·y − λ·v) dt, force −θ·v)",
       false,
       {{"lambda", "inverse time constant of the electrical state", 0.0, true, std::nullopt},
        {"coupling", "product θ·κ of the two coupling coefficients", 0.0, false, std::nullopt}}},
      {EffectId::ColoredNoise, "colored_noise",
       "Ornstein–Uhlenbeck excitation η: dη = −η/tau dt + sqrt(intensity)/tau dW, force +η "
       "(white noise of a22 = intensity as tau → 0)",
       false,
       {{"tau", "correlation time", 0.0, true, std::nullopt},
        {"intensity", "2D of the excitation (spectral level at zero frequency)", 0.0, false,
         std::nullopt}}},
      {EffectId::VelocityDependentNoise, "velocity_dependent_noise", "a22 gains q_y2·y²", true,
       {{"q_y2", "coefficient of y² in a22", 0.0, false, std::nullopt}}},
  };
  return catalogue;
}

const EffectSpec& effect_spec(EffectId id) {
  for (const auto& s : effect_catalogue())
    if (s.id == id) return s;
  throw Error("internal: effect without catalogue entry");
}

double Effect::param(const std::string& key) const {
  auto it = params.find(key);
  if (it == params.end()) throw Error("effect '" + name() + "' has no parameter '" + key + "'");
  return it->second;
}

EffectTerms effect_terms(const Effect& e) {
  EffectTerms t;
  auto p = [&](const char* k) {
    auto it = e.params.find(k);
    return it == e.params.end() ? 0.0 : it->second;
  };
  switch (e.id) {
    case EffectId::AsymmetricStiffness:
      for (int n = 0; n <= 8; n += 2) {
        const double k = p(("k" + std::to_string(n)).c_str());
        if (k != 0.0) t.drift.push_back({Term::monomial(n, 0), -k});
      }
      break;
    case EffectId::CoulombFriction: t.drift.push_back({Term::sign_y(), -p("mu")}); break;
    case EffectId::QuadraticDamping: t.drift.push_back({Term::y_abs_y(), -p("c")}); break;
    case EffectId::NonlinearDamping:
      if (p("c_x2y") != 0.0) t.drift.push_back({Term::monomial(2, 1), -p("c_x2y")});
      if (p("c_y3") != 0.0) t.drift.push_back({Term::monomial(0, 3), -p("c_y3")});
      break;
    case EffectId::VelocityDependentNoise:
      t.diffusion.push_back({Term::monomial(0, 2), p("q_y2")});
      break;
    default: break;
  }
  return t;
}

EffectTerms unit_effect_terms(EffectId id) {
  Effect unit;
  unit.id = id;
  for (const auto& ps : effect_spec(id).params) unit.params[std::string(ps.name)] = 1.0;
  return effect_terms(unit);
}

std::size_t ParameterCovariance::index_of(std::string_view name) const {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return i;
  return names.size();
}

std::string ParameterCovariance::invalid_reason() const {
  const std::size_t n = names.size();
  if (matrix.size() != n * n)
    return "the matrix has " + std::to_string(matrix.size()) + " entries, not " +
           std::to_string(n) + "² for " + std::to_string(n) + " names";
  for (std::size_t i = 0; i < n; ++i) {
    if (index_of(names[i]) != i) return "the name '" + names[i] + "' appears twice";
    if (!((*this)(i, i) >= 0.0)) return "the variance of '" + names[i] + "' is negative or NaN";
    for (std::size_t j = 0; j < n; ++j) {
      const double a = (*this)(i, j), b = (*this)(j, i);
      if (!std::isfinite(a)) return "the entry of '" + names[i] + "', '" + names[j] + "' is not finite";
      if (std::abs(a - b) > 1e-9 * (std::abs(a) + std::abs(b)))
        return "the matrix is not symmetric at '" + names[i] + "', '" + names[j] + "'";
    }
  }
  return "";
}

double Model::drift_coef(std::string_view term) const {
  return coefficient(drift, Term::parse(term));
}
double Model::diffusion_coef(std::string_view term) const {
  return coefficient(diffusion, Term::parse(term));
}
const Effect* Model::find_effect(EffectId id) const {
  for (const auto& e : effects)
    if (e.id == id) return &e;
  return nullptr;
}
bool Model::uses_drive() const {
  for (const auto& tc : drift)
    if (tc.term.depends_on_u()) return true;
  return false;
}

std::string unknown_parameter(EffectId id, const std::string& key) {
  const EffectSpec& spec = effect_spec(id);
  for (const auto& ps : spec.params)
    if (ps.name == key) return "";
  std::string names;
  for (const auto& ps : spec.params) names += (names.empty() ? "" : ", ") + std::string(ps.name);
  return ": effect '" + std::string(spec.name) + "' has no parameter '" + key + "' (its parameters: " + names + ")";
}

namespace {
bool outside_domain(const EffectParamSpec& ps, double v) {
  return v < ps.lower_bound || (ps.strictly_positive && v <= 0.0);
}
std::string domain_text(const EffectParamSpec& ps) {
  if (ps.strictly_positive) return "> 0";
  std::ostringstream os;
  os << ">= " << ps.lower_bound;
  return os.str();
}
}  // namespace

std::string complete_effect(Effect& e, bool require_params) {
  const EffectSpec& spec = effect_spec(e.id);
  const std::string name = e.name();
  for (const auto& [key, value] : e.params) {
    if (auto why = unknown_parameter(e.id, key); !why.empty()) return why;
    if (!std::isfinite(value)) return ".params." + key + " must be finite";
  }
  if (e.id == EffectId::ImpactStop && e.params.count("gap") && !e.params.count("gap_neg"))
    e.params["gap_neg"] = e.params["gap"];
  for (const auto& ps : spec.params) {
    const std::string key(ps.name);
    auto it = e.params.find(key);
    if (it == e.params.end()) {
      if (ps.default_value) {
        if (require_params) e.params[key] = *ps.default_value;
      } else if (require_params) {
        return ": effect '" + name + "' needs parameter '" + key + "' (" + std::string(ps.meaning) + ")";
      }
      continue;
    }
    const double v = it->second;
    if (outside_domain(ps, v))
      return ".params." + key + " must be " + domain_text(ps) + " (got " + std::to_string(v) + ")";
  }
  return "";
}

std::string effect_domain_violation(const Effect& e) {
  for (const auto& ps : effect_spec(e.id).params) {
    auto it = e.params.find(std::string(ps.name));
    if (it == e.params.end() || !outside_domain(ps, it->second)) continue;
    std::ostringstream os;
    os << e.name() << "." << ps.name << " = " << it->second << " is outside its domain (" << domain_text(ps) << ")";
    return os.str();
  }
  return "";
}

void add_effect(Model& m, Effect e, const std::string& where) {
  if (auto why = complete_effect(e, true); !why.empty()) throw Error(where + why);
  if (!effect_spec(e.id).term_like) {
    if (m.find_effect(e.id)) throw Error(where + ": effect '" + e.name() + "' given twice");
    m.effects.push_back(std::move(e));
    return;
  }
  const EffectTerms t = effect_terms(e);
  auto merge = [&](TermList& into, const TermList& add) {
    for (const auto& tc : add) {
      for (const auto& existing : into)
        if (existing.term == tc.term)
          throw Error(where + ": term '" + tc.term.name() + "' is given both as a term and through an effect");
      into.push_back(tc);
    }
    canonicalize(into, where);
  };
  merge(m.drift, t.drift);
  merge(m.diffusion, t.diffusion);
}

void validate_model(const Model& m, const std::string& where) {
  for (const auto& tc : m.drift)
    require(std::isfinite(tc.coef), where + ": drift['" + tc.term.name() + "'] is not finite");
  for (const auto& tc : m.diffusion)
    require(std::isfinite(tc.coef), where + ": diffusion['" + tc.term.name() + "'] is not finite");
  const double a0 = m.a22(0.0, 0.0);
  if (a0 < 0.0) {
    std::ostringstream os;
    os << where << ": diffusion a22(0, 0) = " << a0 << " is negative";
    throw Error(os.str());
  }
}

}  // namespace vehs

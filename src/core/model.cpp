#include "vehs/core/model.hpp"

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "vehs/core/error.hpp"

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
      {EffectId::ImpactStop, "impact_stop",
       "end stops: force −k_stop·(x − gap) for x > gap and −k_stop·(x + gap_neg) for x < −gap_neg",
       false,
       {{"k_stop", "stiffness of the stops", 0.0, true, std::nullopt},
        {"gap", "distance from x = 0 to the positive stop", 0.0, true, std::nullopt},
        {"gap_neg", "distance to the negative stop (default: gap)", 0.0, true, std::nullopt}}},
      {EffectId::HarmonicForcing, "harmonic_forcing", "force amplitude·cos(omega·t + phase)", false,
       {{"amplitude", "forcing amplitude", 0.0, false, std::nullopt},
        {"omega", "angular frequency", 0.0, true, std::nullopt},
        {"phase", "phase at t = 0 (radians)", kFree, false, 0.0}}},
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

namespace {

double finite_number(const nlohmann::json& v, const std::string& where) {
  if (!v.is_number()) throw Error(where + " must be a number (got " + v.dump() + ")");
  const double d = v.get<double>();
  if (!std::isfinite(d)) throw Error(where + " must be finite");
  return d;
}

TermList terms_from_json(const nlohmann::json& j, const std::string& where) {
  if (!j.is_object())
    throw Error(where + " must be an object mapping term names to coefficients");
  TermList list;
  for (auto it = j.begin(); it != j.end(); ++it) {
    Term term;
    try {
      term = Term::parse(it.key());
    } catch (const Error& e) {
      throw Error(where + ": " + e.what());
    }
    list.push_back({term, finite_number(it.value(), where + "[\"" + it.key() + "\"]")});
  }
  canonicalize(list, where);
  return list;
}

std::map<std::string, double> stderr_from_json(const nlohmann::json& j, const std::string& where) {
  std::map<std::string, double> m;
  if (!j.is_object()) throw Error(where + " must be an object");
  for (auto it = j.begin(); it != j.end(); ++it) {
    (void)Term::parse(it.key());
    m[it.key()] = finite_number(it.value(), where + "[\"" + it.key() + "\"]");
  }
  return m;
}

void merge_terms(TermList& into, const TermList& add, const std::string& where) {
  for (const auto& tc : add) {
    for (const auto& existing : into)
      if (existing.term == tc.term)
        throw Error(where + ": term '" + tc.term.name() +
                    "' is given both as a term and through an effect");
    into.push_back(tc);
  }
  canonicalize(into, where);
}

}  // namespace

Effect effect_from_json(const nlohmann::json& j, const std::string& where, bool require_params) {
  Effect e;
  nlohmann::json params = nlohmann::json::object();
  std::string name;
  if (j.is_string()) {
    name = j.get<std::string>();
  } else if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it)
      if (it.key() != "name" && it.key() != "params" && it.key() != "stderr")
        throw Error(where + ": unknown key '" + it.key() + "' (expected name, params, stderr)");
    if (!j.contains("name") || !j["name"].is_string())
      throw Error(where + ": an effect needs a string 'name'");
    name = j["name"].get<std::string>();
    if (j.contains("params")) params = j["params"];
    if (!params.is_object()) throw Error(where + ".params must be an object");
    if (j.contains("stderr")) {
      if (!j["stderr"].is_object()) throw Error(where + ".stderr must be an object");
      for (auto it = j["stderr"].begin(); it != j["stderr"].end(); ++it)
        e.stderr_[it.key()] = finite_number(it.value(), where + ".stderr." + it.key());
    }
  } else {
    throw Error(where + " must be an effect name or {\"name\": ..., \"params\": {...}}");
  }
  e.id = enum_from_string(kEffectNames, name, where + ".name");
  const EffectSpec& spec = effect_spec(e.id);
  for (auto it = params.begin(); it != params.end(); ++it) {
    bool known = false;
    for (const auto& ps : spec.params) known = known || ps.name == it.key();
    if (!known) {
      std::string names;
      for (const auto& ps : spec.params) names += (names.empty() ? "" : ", ") + std::string(ps.name);
      throw Error(where + ": effect '" + name + "' has no parameter '" + it.key() +
                  "' (its parameters: " + names + ")");
    }
    e.params[it.key()] = finite_number(it.value(), where + ".params." + it.key());
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
        throw Error(where + ": effect '" + name + "' needs parameter '" + key + "' (" +
                    std::string(ps.meaning) + ")");
      }
      continue;
    }
    const double v = it->second;
    if (v < ps.lower_bound || (ps.strictly_positive && v <= 0.0))
      throw Error(where + ".params." + key + " must be " +
                  (ps.strictly_positive ? "> 0" : ">= " + std::to_string(ps.lower_bound)) +
                  " (got " + std::to_string(v) + ")");
  }
  return e;
}

nlohmann::ordered_json effect_to_json(const Effect& e) {
  nlohmann::ordered_json j;
  j["name"] = e.name();
  j["params"] = nlohmann::ordered_json::object();
  for (const auto& [k, v] : e.params) j["params"][k] = v;
  if (!e.stderr_.empty()) {
    j["stderr"] = nlohmann::ordered_json::object();
    for (const auto& [k, v] : e.stderr_) j["stderr"][k] = v;
  }
  return j;
}

Model model_from_json(const nlohmann::json& j, const std::string& where) {
  if (!j.is_object()) throw Error(where + ": a model must be a JSON object");
  Model m;
  if (!j.contains("drift")) throw Error(where + ": model has no 'drift'");
  if (!j.contains("diffusion")) throw Error(where + ": model has no 'diffusion'");
  m.drift = terms_from_json(j["drift"], where + ": drift");
  m.diffusion = terms_from_json(j["diffusion"], where + ": diffusion");
  for (const auto& tc : m.diffusion)
    if (tc.term.depends_on_u() || tc.term.kind == TermKind::SignY)
      throw Error(where + ": diffusion term '" + tc.term.name() + "' is not allowed");
  if (j.contains("stderr")) {
    const auto& s = j["stderr"];
    if (!s.is_object()) throw Error(where + ": stderr must be an object");
    if (s.contains("drift")) m.drift_stderr = stderr_from_json(s["drift"], where + ": stderr.drift");
    if (s.contains("diffusion"))
      m.diffusion_stderr = stderr_from_json(s["diffusion"], where + ": stderr.diffusion");
  }
  if (j.contains("effects")) {
    const auto& ef = j["effects"];
    if (!ef.is_array()) throw Error(where + ": effects must be a list");
    for (std::size_t i = 0; i < ef.size(); ++i) {
      const std::string w = where + ": effects[" + std::to_string(i) + "]";
      Effect e = effect_from_json(ef[i], w, true);
      const EffectSpec& spec = effect_spec(e.id);
      if (spec.term_like) {
        EffectTerms t = effect_terms(e);
        merge_terms(m.drift, t.drift, w);
        merge_terms(m.diffusion, t.diffusion, w);
      } else {
        if (m.find_effect(e.id)) throw Error(w + ": effect '" + e.name() + "' given twice");
        m.effects.push_back(std::move(e));
      }
    }
  }
  for (auto it = j.begin(); it != j.end(); ++it)
    if (it.key() != "drift" && it.key() != "diffusion" && it.key() != "stderr" &&
        it.key() != "effects")
      m.extra[it.key()] = it.value();
  return m;
}

Model load_model_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open model file");
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::parse_error& e) {
    throw Error(path + ": not valid JSON (" + std::string(e.what()) + ")");
  }
  return model_from_json(j, path);
}

Model model_from_config_value(const nlohmann::json& value, const std::string& where) {
  if (value.is_string()) return load_model_file(value.get<std::string>());
  if (value.is_object()) return model_from_json(value, where);
  throw Error(where + " must be a model object or the path of a model file");
}

nlohmann::ordered_json model_to_json(const Model& m) {
  nlohmann::ordered_json j;
  auto terms = [](const TermList& list) {
    nlohmann::ordered_json o = nlohmann::ordered_json::object();
    for (const auto& tc : list)
      if (tc.coef != 0.0) o[tc.term.name()] = tc.coef;
    return o;
  };
  j["drift"] = terms(m.drift);
  j["diffusion"] = terms(m.diffusion);
  if (!m.drift_stderr.empty() || !m.diffusion_stderr.empty()) {
    nlohmann::ordered_json s;
    s["drift"] = nlohmann::ordered_json::object();
    s["diffusion"] = nlohmann::ordered_json::object();
    // keep the model's term order
    for (const auto& tc : m.drift)
      if (auto it = m.drift_stderr.find(tc.term.name()); it != m.drift_stderr.end())
        s["drift"][it->first] = it->second;
    for (const auto& tc : m.diffusion)
      if (auto it = m.diffusion_stderr.find(tc.term.name()); it != m.diffusion_stderr.end())
        s["diffusion"][it->first] = it->second;
    j["stderr"] = s;
  }
  j["effects"] = nlohmann::ordered_json::array();
  for (const auto& e : m.effects) j["effects"].push_back(effect_to_json(e));
  for (auto it = m.extra.begin(); it != m.extra.end(); ++it) j[it.key()] = it.value();
  return j;
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

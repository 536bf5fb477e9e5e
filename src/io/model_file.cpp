#include "vehs/io/model_file.hpp"

#include <cmath>
#include <cstdint>

#include "vehs/core/error.hpp"
#include "vehs/io/atomic_file.hpp"
#include "vehs/io/json_file.hpp"
#include "vehs/io/path_text.hpp"

namespace vehs {

namespace {

using OJ = nlohmann::ordered_json;

double finite_number(const nlohmann::json& v, const std::string& where) {
  if (!v.is_number()) throw Error(where + " must be a number (got " + json_excerpt(v) + ")");
  const double d = v.get<double>();
  if (!std::isfinite(d)) throw Error(where + " must be finite");
  return d;
}

TermList terms_from_json(const nlohmann::json& j, const std::string& where) {
  if (!j.is_object()) throw Error(where + " must be an object mapping term names to coefficients");
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

// ---- the fit: "estimator" and "sampling"

double optional_number(const nlohmann::json& o, const char* key, double fallback, const std::string& where) {
  return o.contains(key) ? finite_number(o[key], where + "." + key) : fallback;
}

int positive_integer(const nlohmann::json& o, const char* key, const std::string& where) {
  if (!o.contains(key)) return 0;
  const auto& v = o[key];
  if (!v.is_number_integer() || v.get<long long>() < 1 || v.get<long long>() > 1000000)
    throw Error(where + "." + key + " must be an integer >= 1 (got " + json_excerpt(v) + ")");
  return v.get<int>();
}

std::vector<double> number_array(const nlohmann::json& o, const char* key, const std::string& where) {
  std::vector<double> out;
  if (!o.contains(key)) return out;
  if (!o[key].is_array()) throw Error(where + "." + key + " must be a list of numbers");
  for (std::size_t i = 0; i < o[key].size(); ++i)
    out.push_back(finite_number(o[key][i], where + "." + key + "[" + std::to_string(i) + "]"));
  return out;
}

std::string optional_string(const nlohmann::json& o, const char* key, const std::string& where) {
  if (!o.contains(key)) return "";
  if (!o[key].is_string()) throw Error(where + "." + key + " must be a string");
  return o[key].get<std::string>();
}

/// `likelihood.bias_correction`: {"datasets": B, "seed": s, "max_shift_se": d, "skipped": why}.
void bias_correction_from_json(const nlohmann::json& b, const std::string& w, LikelihoodFit& f) {
  if (!b.is_object()) throw Error(w + " must be an object");
  for (auto it = b.begin(); it != b.end(); ++it)
    if (it.key() != "datasets" && it.key() != "seed" && it.key() != "max_shift_se" && it.key() != "skipped")
      throw Error(w + ": unknown key '" + it.key() + "' (datasets, seed, max_shift_se, skipped)");
  if (!b.contains("datasets")) throw Error(w + ".datasets is missing");
  const auto& B = b["datasets"];
  if (!B.is_number_integer() || B.get<long long>() < 0 || B.get<long long>() > 1000)
    throw Error(w + ".datasets must be an integer in [0, 1000] (got " + json_excerpt(B) + ")");
  f.bias_correction_datasets = B.get<int>();
  if (b.contains("seed")) {
    const auto& s = b["seed"];
    if (!s.is_number_unsigned()) throw Error(w + ".seed must be an integer >= 0 (got " + json_excerpt(s) + ")");
    f.bias_correction_seed = s.get<std::uint64_t>();
  }
  f.bias_correction_max_shift_se = optional_number(b, "max_shift_se", 0.0, w);
  if (f.bias_correction_max_shift_se < 0.0) throw Error(w + ".max_shift_se must be >= 0");
  f.bias_correction_skipped = optional_string(b, "skipped", w);
}

LikelihoodFit likelihood_from_json(const nlohmann::json& l, const std::string& w) {
  if (!l.is_object()) throw Error(w + " must be an object");
  LikelihoodFit f;
  f.measurement_sd = optional_number(l, "measurement_sd", 0.0, w);
  if (f.measurement_sd < 0.0) throw Error(w + ".measurement_sd must be >= 0");
  f.record_phases = number_array(l, "record_phases", w);
  f.log_likelihood = optional_number(l, "log_likelihood", 0.0, w);
  f.bic = optional_number(l, "bic", 0.0, w);
  const double n = optional_number(l, "observations", 0.0, w);
  if (n < 0.0 || n != std::floor(n)) throw Error(w + ".observations must be a whole number >= 0");
  f.observations = static_cast<std::size_t>(n);
  f.substeps = positive_integer(l, "substeps", w);
  f.selection = optional_string(l, "selection", w);
  f.covariance_method = optional_string(l, "covariance_method", w);
  f.reason = optional_string(l, "reason", w);
  if (l.contains("converged")) {
    if (!l["converged"].is_boolean()) throw Error(w + ".converged must be true or false");
    f.converged = l["converged"].get<bool>();
  }
  if (l.contains("parameters")) {
    if (!l["parameters"].is_array()) throw Error(w + ".parameters must be a list of names");
    for (const auto& p : l["parameters"]) {
      if (!p.is_string()) throw Error(w + ".parameters must be a list of names");
      f.parameters.push_back(p.get<std::string>());
    }
  }
  f.values = number_array(l, "values", w);
  if (!f.values.empty() && f.values.size() != f.parameters.size())
    throw Error(w + ".values needs one value per parameter (" + std::to_string(f.parameters.size()) + ")");
  if (l.contains("covariance")) {
    const auto& c = l["covariance"];
    const std::size_t k = f.parameters.size();
    if (!c.is_array() || c.size() != k) throw Error(w + ".covariance must be a " + std::to_string(k) + " x " + std::to_string(k) + " matrix");
    for (std::size_t i = 0; i < k; ++i) {
      if (!c[i].is_array() || c[i].size() != k)
        throw Error(w + ".covariance must be a " + std::to_string(k) + " x " + std::to_string(k) + " matrix");
      for (std::size_t m = 0; m < k; ++m)
        f.covariance.push_back(finite_number(c[i][m], w + ".covariance[" + std::to_string(i) + "][" + std::to_string(m) + "]"));
    }
  }
  if (l.contains("bias_correction")) bias_correction_from_json(l["bias_correction"], w + ".bias_correction", f);
  return f;
}

OJ likelihood_to_json(const LikelihoodFit& f) {
  OJ l;
  l["measurement_sd"] = f.measurement_sd;
  if (!f.record_phases.empty()) l["record_phases"] = f.record_phases;
  l["log_likelihood"] = f.log_likelihood;
  l["bic"] = f.bic;
  l["observations"] = f.observations;
  if (f.substeps > 0) l["substeps"] = f.substeps;
  if (!f.selection.empty()) l["selection"] = f.selection;
  if (!f.covariance_method.empty()) l["covariance_method"] = f.covariance_method;
  l["converged"] = f.converged;
  if (!f.reason.empty()) l["reason"] = f.reason;
  l["parameters"] = f.parameters;
  if (!f.values.empty()) l["values"] = f.values;
  const std::size_t k = f.parameters.size();
  if (f.covariance.size() == k * k) {
    OJ c = OJ::array();
    for (std::size_t i = 0; i < k; ++i)
      c.push_back(std::vector<double>(f.covariance.begin() + long(i * k), f.covariance.begin() + long((i + 1) * k)));
    l["covariance"] = c;
  }
  if (f.bias_correction_datasets > 0 || !f.bias_correction_skipped.empty()) {
    OJ b;
    b["datasets"] = f.bias_correction_datasets;
    if (f.bias_correction_datasets > 0) {
      b["seed"] = f.bias_correction_seed;
      b["max_shift_se"] = f.bias_correction_max_shift_se;
    }
    if (!f.bias_correction_skipped.empty()) b["skipped"] = f.bias_correction_skipped;
    l["bias_correction"] = b;
  }
  return l;
}

std::optional<FitInfo> fit_from_json(const nlohmann::json& j, const std::string& where) {
  const bool has_est = j.contains("estimator"), has_samp = j.contains("sampling");
  const bool has_lik = j.contains("likelihood");
  if (!has_est && !has_samp && !has_lik) return std::nullopt;
  FitInfo f;
  if (has_lik) f.likelihood = likelihood_from_json(j["likelihood"], where + ": likelihood");
  if (has_est) {
    const auto& e = j["estimator"];
    const std::string w = where + ": estimator";
    if (!e.is_object()) throw Error(w + " must be an object");
    if (e.contains("used")) {
      if (!e["used"].is_string()) throw Error(w + ".used must be a string");
      f.estimator = enum_from_string(kEstimatorNames, e["used"].get<std::string>(), w + ".used");
    }
    f.stride = positive_integer(e, "stride", w);
    if (e.contains("input")) {
      if (!e["input"].is_string()) throw Error(w + ".input must be a string");
      f.input = enum_from_string(kInputInterpolationNames, e["input"].get<std::string>(), w + ".input");
    }
  }
  if (has_samp) {
    const auto& s = j["sampling"];
    const std::string w = where + ": sampling";
    if (!s.is_object()) throw Error(w + " must be an object");
    SamplingDiagnosis& d = f.sampling;
    d.dt = optional_number(s, "dt", 0.0, w);
    if (d.dt < 0.0) throw Error(w + ".dt must be > 0");
    d.stride = positive_integer(s, "pilot_stride", w);
    d.rho_1 = optional_number(s, "rho_lag1", SamplingDiagnosis::kUnknown, w);
    d.rho_k = optional_number(s, "rho_lag_k", SamplingDiagnosis::kUnknown, w);
    d.rho_2k = optional_number(s, "rho_lag_2k", SamplingDiagnosis::kUnknown, w);
    d.rho_3k = optional_number(s, "rho_lag_3k", SamplingDiagnosis::kUnknown, w);
    d.noise_share = optional_number(s, "noise_share", SamplingDiagnosis::kUnknown, w);
    d.sensor_noise_sd = optional_number(s, "sensor_noise_sd", 0.0, w);
    d.quantisation_step = optional_number(s, "quantisation_step", 0.0, w);
    if (!(d.sensor_noise_sd >= 0.0)) throw Error(w + ".sensor_noise_sd must be >= 0");
    if (!(d.quantisation_step >= 0.0)) throw Error(w + ".quantisation_step must be >= 0");
    if (s.contains("verdict")) {
      if (!s["verdict"].is_string()) throw Error(w + ".verdict must be a string");
      d.verdict = enum_from_string(kSamplingVerdictNames, s["verdict"].get<std::string>(), w + ".verdict");
    }
  }
  return f;
}

/// Writes the stated fields of the fit over `est` and `samp` (keys keep their position).
void fit_to_json(const FitInfo& f, OJ& est, OJ& samp) {
  if (f.estimator != Estimator::Auto) est["used"] = enum_to_string(kEstimatorNames, f.estimator);
  if (f.stride > 0) est["stride"] = f.stride;
  if (f.input != InputInterpolation::ZeroOrderHold || f.likelihood) est["input"] = enum_to_string(kInputInterpolationNames, f.input);
  if (f.likelihood) est["refined"] = "likelihood";
  const SamplingDiagnosis& d = f.sampling;
  if (d.dt > 0.0) samp["dt"] = d.dt;
  if (d.stride > 0) samp["pilot_stride"] = d.stride;
  auto number = [&](const char* key, double v) {
    if (std::isfinite(v)) samp[key] = v;
  };
  number("rho_lag1", d.rho_1);
  number("rho_lag_k", d.rho_k);
  number("rho_lag_2k", d.rho_2k);
  number("rho_lag_3k", d.rho_3k);
  number("noise_share", d.noise_share);
  if (d.verdict != SamplingVerdict::Unknown) samp["verdict"] = enum_to_string(kSamplingVerdictNames, d.verdict);
  if (f.estimator == Estimator::Noisy || d.sensor_noise_sd > 0.0) samp["sensor_noise_sd"] = d.sensor_noise_sd;
  if (d.quantisation_step > 0.0) samp["quantisation_step"] = d.quantisation_step;
}

OJ terms_to_json(const TermList& list) {
  OJ o = OJ::object();
  for (const auto& tc : list)
    if (tc.coef != 0.0) o[tc.term.name()] = tc.coef;
  return o;
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
    if (!j.contains("name") || !j["name"].is_string()) throw Error(where + ": an effect needs a string 'name'");
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
  for (auto it = params.begin(); it != params.end(); ++it) {
    if (auto why = unknown_parameter(e.id, it.key()); !why.empty()) throw Error(where + why);
    e.params[it.key()] = finite_number(it.value(), where + ".params." + it.key());
  }
  if (auto why = complete_effect(e, require_params); !why.empty()) throw Error(where + why);
  return e;
}

nlohmann::ordered_json effect_to_json(const Effect& e) {
  OJ j;
  j["name"] = e.name();
  j["params"] = OJ::object();
  for (const auto& [k, v] : e.params) j["params"][k] = v;
  if (!e.stderr_.empty()) {
    j["stderr"] = OJ::object();
    for (const auto& [k, v] : e.stderr_) j["stderr"][k] = v;
  }
  return j;
}

bool is_user_effect_json(const nlohmann::json& j) {
  return j.is_object() && (j.contains("drift") || j.contains("diffusion"));
}

UserEffect user_effect_from_json(const nlohmann::json& j, const std::string& where) {
  if (!j.is_object()) throw Error(where + " must be a user effect {\"name\": ..., \"drift\": {\"param\": \"term\"}}");
  for (auto it = j.begin(); it != j.end(); ++it)
    if (it.key() != "name" && it.key() != "drift" && it.key() != "diffusion")
      throw Error(where + ": unknown key '" + it.key() + "' of a user effect (expected name, drift, diffusion)");
  if (!j.contains("name") || !j["name"].is_string()) throw Error(where + ": a user effect needs a string 'name'");
  UserEffect e;
  e.name = j["name"].get<std::string>();
  for (const bool diffusion : {false, true}) {
    const char* key = diffusion ? "diffusion" : "drift";
    if (!j.contains(key)) continue;
    const std::string at = where + "." + key;
    if (!j[key].is_object()) throw Error(at + " must be an object {\"param\": \"term\", ...}");
    for (auto it = j[key].begin(); it != j[key].end(); ++it) {
      if (!it.value().is_string()) throw Error(at + "." + it.key() + " must be a term (a string)");
      try {
        e.params.push_back({it.key(), Term::parse(it.value().get<std::string>()), diffusion});
      } catch (const Error& err) {
        throw Error(at + "." + it.key() + ": " + err.what());
      }
    }
  }
  if (auto why = e.invalid_reason(); !why.empty()) throw Error(where + ": " + why);
  return e;
}

nlohmann::ordered_json user_effect_to_json(const UserEffect& e) {
  OJ j;
  j["name"] = e.name;
  for (const bool diffusion : {false, true}) {
    OJ terms = OJ::object();
    for (const auto& p : e.params)
      if (p.diffusion == diffusion) terms[p.name] = p.term.name();
    if (!terms.empty()) j[diffusion ? "diffusion" : "drift"] = terms;
  }
  return j;
}

namespace {

// ---- "covariance": {"parameters": [names], "matrix": [[row], ...]}

ParameterCovariance covariance_from_json(const nlohmann::json& j, const std::string& where) {
  if (!j.is_object() || !j.contains("parameters") || !j.contains("matrix") || !j["parameters"].is_array() ||
      !j["matrix"].is_array())
    throw Error(where + " must be an object with a list 'parameters' and a list of rows 'matrix'");
  ParameterCovariance c;
  for (const auto& n : j["parameters"]) {
    if (!n.is_string()) throw Error(where + ".parameters must be a list of names");
    c.names.push_back(n.get<std::string>());
  }
  const auto& rows = j["matrix"];
  if (rows.size() != c.names.size())
    throw Error(where + ".matrix has " + std::to_string(rows.size()) + " rows for " +
                std::to_string(c.names.size()) + " parameters");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::string w = where + ".matrix[" + std::to_string(i) + "]";
    if (!rows[i].is_array() || rows[i].size() != c.names.size())
      throw Error(w + " must be a row of " + std::to_string(c.names.size()) + " numbers");
    for (std::size_t k = 0; k < rows[i].size(); ++k)
      c.matrix.push_back(finite_number(rows[i][k], w + "[" + std::to_string(k) + "]"));
  }
  if (auto why = c.invalid_reason(); !why.empty()) throw Error(where + ": " + why);
  return c;
}

OJ covariance_to_json(const ParameterCovariance& c) {
  OJ j;
  j["parameters"] = c.names;
  j["matrix"] = OJ::array();
  for (std::size_t i = 0; i < c.size(); ++i) {
    OJ row = OJ::array();
    for (std::size_t k = 0; k < c.size(); ++k) row.push_back(c(i, k));
    j["matrix"].push_back(row);
  }
  return j;
}

bool is_model_key(const std::string& key) {
  return key == "drift" || key == "diffusion" || key == "stderr" || key == "effects" || key == "covariance";
}

}  // namespace

Model model_from_json(const nlohmann::json& j, const std::string& where, nlohmann::ordered_json* sections) {
  if (!j.is_object()) throw Error(where + ": a model must be a JSON object");
  Model m;
  if (!j.contains("drift")) throw Error(where + ": model has no 'drift'");
  if (!j.contains("diffusion")) throw Error(where + ": model has no 'diffusion'");
  m.drift = terms_from_json(j["drift"], where + ": drift");
  m.diffusion = terms_from_json(j["diffusion"], where + ": diffusion");
  for (const auto& tc : m.diffusion)
    if (!allowed_in_diffusion(tc.term)) throw Error(where + ": diffusion term '" + tc.term.name() + "' is not allowed");
  if (j.contains("stderr")) {
    const auto& s = j["stderr"];
    if (!s.is_object()) throw Error(where + ": stderr must be an object");
    if (s.contains("drift")) m.drift_stderr = stderr_from_json(s["drift"], where + ": stderr.drift");
    if (s.contains("diffusion")) m.diffusion_stderr = stderr_from_json(s["diffusion"], where + ": stderr.diffusion");
  }
  if (j.contains("effects")) {
    const auto& ef = j["effects"];
    if (!ef.is_array()) throw Error(where + ": effects must be a list");
    for (std::size_t i = 0; i < ef.size(); ++i) {
      const std::string w = where + ": effects[" + std::to_string(i) + "]";
      add_effect(m, effect_from_json(ef[i], w, true), w);
    }
  }
  m.fit = fit_from_json(j, where);
  if (j.contains("covariance")) m.covariance = covariance_from_json(j["covariance"], where + ": covariance");
  if (sections)
    for (auto it = j.begin(); it != j.end(); ++it)
      if (!is_model_key(it.key())) (*sections)[it.key()] = it.value();
  return m;
}

ModelFile read_model_file(const std::string& path) {
  const nlohmann::json j = read_json_file(path, "model file");
  ModelFile f;
  f.model = model_from_json(j, path, &f.sections);
  return f;
}

Model load_model_file(const std::string& path) { return read_model_file(path).model; }

ModelFile model_from_config_value(const nlohmann::json& value, const std::string& where) {
  if (value.is_string()) {
    check_path_text(value.get<std::string>(), where);
    return read_model_file(value.get<std::string>());
  }
  if (!value.is_object()) throw Error(where + " must be a model object or the path of a model file");
  ModelFile f;
  f.model = model_from_json(value, where, &f.sections);
  return f;
}

nlohmann::ordered_json model_to_json(const Model& m, const nlohmann::ordered_json& sections) {
  OJ j;
  j["drift"] = terms_to_json(m.drift);
  j["diffusion"] = terms_to_json(m.diffusion);
  if (!m.drift_stderr.empty() || !m.diffusion_stderr.empty()) {
    OJ s;
    s["drift"] = OJ::object();
    s["diffusion"] = OJ::object();
    // keep the model's term order
    for (const auto& tc : m.drift)
      if (auto it = m.drift_stderr.find(tc.term.name()); it != m.drift_stderr.end()) s["drift"][it->first] = it->second;
    for (const auto& tc : m.diffusion)
      if (auto it = m.diffusion_stderr.find(tc.term.name()); it != m.diffusion_stderr.end())
        s["diffusion"][it->first] = it->second;
    j["stderr"] = s;
  }
  j["effects"] = OJ::array();
  for (const auto& e : m.effects) j["effects"].push_back(effect_to_json(e));
  if (!m.covariance.empty()) j["covariance"] = covariance_to_json(m.covariance);
  for (auto it = sections.begin(); it != sections.end(); ++it)
    if (!is_model_key(it.key())) j[it.key()] = it.value();
  if (m.fit) {
    OJ est = j.contains("estimator") && j["estimator"].is_object() ? j["estimator"] : OJ::object();
    OJ samp = j.contains("sampling") && j["sampling"].is_object() ? j["sampling"] : OJ::object();
    fit_to_json(*m.fit, est, samp);
    if (!est.empty()) j["estimator"] = est;
    if (!samp.empty()) j["sampling"] = samp;
    if (m.fit->likelihood) j["likelihood"] = likelihood_to_json(*m.fit->likelihood);
  }
  return j;
}

void write_model_file(const std::string& path, const Model& m, const nlohmann::ordered_json& sections) {
  write_json_atomically(path, model_to_json(m, sections));
}

}  // namespace vehs

#include "vehs/likelihood/detail/parameterization.hpp"

#include <algorithm>
#include <cmath>

#include "vehs/core/error.hpp"
#include "vehs/likelihood/detail/gaussian_expectations.hpp"

namespace vehs::likelihood::detail {

Structure Structure::of(const Model& m, const std::string& where) {
  Structure st;
  using Moments = GaussianMoments<double>;
  auto note_powers = [&](const Term& t, const char* what) {
    if (t.kind != TermKind::Monomial) return;
    if (t.px >= Moments::kMaxA || t.py >= Moments::kMaxB)
      throw Error(where + ": " + what + " term '" + t.name() + "' has a power beyond x^" +
                  std::to_string(Moments::kMaxA - 1) + " or y^" +
                  std::to_string(Moments::kMaxB - 1) + " (the filter's moment tables)");
    st.max_px = std::max(st.max_px, t.px);
    st.max_py = std::max(st.max_py, t.py);
  };
  for (const auto& tc : m.drift) {
    if (tc.coef == 0.0) continue;
    note_powers(tc.term, "drift");
    st.drift.push_back(tc.term);
    st.drive = st.drive || tc.term.depends_on_u();
    st.friction = st.friction || tc.term.kind == TermKind::SignY;
  }
  for (const auto& tc : m.diffusion) {
    if (tc.coef == 0.0) continue;
    if (tc.term.kind == TermKind::SignY || tc.term.depends_on_u())
      throw Error(where + ": diffusion term '" + tc.term.name() + "' is not allowed");
    note_powers(tc.term, "diffusion");
    st.diffusion.push_back(tc.term);
  }
  // moment-table shape: (px, py), (px − 1, py), (px, py − 1) for drift terms, (px, py) for a22
  auto need = [&](int a, int b) {
    if (a < 0 || b < 0) return;
    for (int bb = 0; bb <= b; ++bb) st.a_max_by_b[bb] = std::max(st.a_max_by_b[bb], a);
  };
  for (const auto& t : st.drift) {
    if (t.kind == TermKind::Monomial) {
      need(t.px, t.py);
      need(t.px - 1, t.py);
      need(t.px, t.py - 1);
    } else if (t.kind != TermKind::Drive) {
      st.needs_sd = true;
    }
  }
  for (const auto& t : st.diffusion) {
    if (t.kind == TermKind::Monomial) need(t.px, t.py);
    else st.needs_sd = true;
  }
  for (const auto& e : m.effects) {
    if (e.id == EffectId::ImpactStop) st.needs_sd = true;
    switch (e.id) {
      case EffectId::ImpactStop: st.impact = true; break;
      case EffectId::HarmonicForcing: st.harmonic = true; break;
      case EffectId::ElectromechanicalCoupling: st.electro = true; break;
      case EffectId::ColoredNoise: st.colored = true; break;
      default:
        throw Error(where + ": effect '" + e.name() +
                    "' should have been expanded into drift/diffusion terms");
    }
  }
  return st;
}

namespace {

double effect_value(const Effect& e, const std::string& key, const std::string& where) {
  auto it = e.params.find(key);
  if (it != e.params.end()) return it->second;
  if (e.id == EffectId::ImpactStop && key == "gap_neg") return effect_value(e, "gap", where);
  if (e.id == EffectId::HarmonicForcing && key == "phase") return 0.0;
  throw Error(where + ": effect '" + e.name() + "' needs a start value for '" + key + "'");
}

bool positive_effect_param(EffectId id, const std::string& key) {
  if (id == EffectId::ColoredNoise) return true;  // tau, intensity
  for (const auto& ps : effect_spec(id).params)
    if (ps.name == key) return ps.strictly_positive;
  return false;
}

}  // namespace

Parameterization::Parameterization(const ObservedModel& start, const FitChoice& choice,
                                   std::size_t records, const std::string& where)
    : start_(start), structure_(Structure::of(start.model, where)), records_(records) {
  const Model& m = start.model;
  auto natural = [&](const std::string& name) {
    return std::find(choice.natural_scale.begin(), choice.natural_scale.end(), name) !=
           choice.natural_scale.end();
  };
  if (!(std::isfinite(start.measurement_sd) && start.measurement_sd >= 0.0))
    throw Error(where + ": measurement_sd must be finite and >= 0");
  for (const auto& tc : m.drift)
    if (tc.coef != 0.0) {
      params_.push_back({"drift[" + tc.term.name() + "]", ParameterKind::Drift,
                         int(base_.drift.size()), {}, {}, false});
      initial_.push_back(tc.coef);
      base_.drift.push_back(tc.coef);
    }
  for (const auto& tc : m.diffusion)
    if (tc.coef != 0.0) {
      const std::string name = "diffusion[" + tc.term.name() + "]";
      const bool log_scale = tc.term == Term::monomial(0, 0) && tc.coef > 0.0 && !natural(name);
      params_.push_back({name, ParameterKind::Diffusion,
                         int(base_.diffusion.size()), {}, {}, log_scale});
      initial_.push_back(log_scale ? std::log(tc.coef) : tc.coef);
      base_.diffusion.push_back(tc.coef);
    }
  const Effect* harmonic = nullptr;
  for (const auto& e : m.effects) {
    if (e.id == EffectId::HarmonicForcing) harmonic = &e;
    for (const auto& ps : effect_spec(e.id).params) {
      const std::string key(ps.name);
      const double v = effect_value(e, key, where);
      ParameterInfo info{e.name() + "." + key, ParameterKind::Effect, -1, e.id, key, false};
      target(info, base_) = v;
      if (e.id == EffectId::HarmonicForcing && key == "phase" && choice.per_record_phase) continue;
      const bool log_scale = positive_effect_param(e.id, key) && !natural(info.name);
      if (log_scale && !(v > 0.0))
        throw Error(where + ": " + info.name + " must start > 0 (got " + std::to_string(v) + ")");
      info.log_scale = log_scale;
      params_.push_back(info);
      initial_.push_back(log_scale ? std::log(v) : v);
    }
  }
  base_.measurement_var = start.measurement_sd * start.measurement_sd;
  if (choice.fit_measurement_noise) {
    if (!(start.measurement_sd > 0.0))
      throw Error(where + ": measurement_sd needs a start value > 0 to be estimated");
    params_.push_back({"measurement_sd", ParameterKind::MeasurementSd, -1, {}, {}, true});
    initial_.push_back(std::log(start.measurement_sd));
  }
  // fixed parameters: removed from θ (their start values stay in base_)
  for (const auto& name : choice.fixed) {
    auto it = std::find_if(params_.begin(), params_.end(),
                           [&](const ParameterInfo& p) { return p.name == name; });
    if (it == params_.end())
      throw Error(where + ": cannot hold '" + name + "' fixed: no such free parameter");
    initial_.erase(initial_.begin() + (it - params_.begin()));
    params_.erase(it);
  }
  shared_ = params_.size();
  // per-record phases
  if (!start.record_phases.empty() && start.record_phases.size() != records)
    throw Error(where + ": " + std::to_string(start.record_phases.size()) +
                " record phases for " + std::to_string(records) + " records");
  start_phases_ = start.record_phases;
  if (choice.per_record_phase) {
    if (!harmonic) throw Error(where + ": per-record phases need a harmonic_forcing effect");
    local_phase_ = true;
    for (std::size_t r = 0; r < records; ++r) {
      params_.push_back({"phase[" + std::to_string(r) + "]", ParameterKind::RecordPhase, int(r),
                         EffectId::HarmonicForcing, "phase", false});
      initial_.push_back(start_phases_.empty() ? base_.forcing.phase : start_phases_[r]);
    }
  }
}

ObservedModel Parameterization::model_at(const std::vector<double>& theta) const {
  ObservedModel out = start_;
  Coefficients<double> c;
  const double no_phase = 0.0;
  coefficients<double>(theta.data(), &no_phase, c);
  std::size_t di = 0, qi = 0;
  for (auto& tc : out.model.drift)
    if (tc.coef != 0.0) tc.coef = c.drift[di++];
  for (auto& tc : out.model.diffusion)
    if (tc.coef != 0.0) tc.coef = c.diffusion[qi++];
  for (auto& e : out.model.effects)
    for (const auto& ps : effect_spec(e.id).params) {
      const std::string key(ps.name);
      ParameterInfo info{"", ParameterKind::Effect, -1, e.id, key, false};
      e.params[key] = target(info, c);
    }
  out.measurement_sd = std::sqrt(c.measurement_var);
  if (local_phase_) {
    out.record_phases.resize(records_);
    for (std::size_t r = 0; r < records_; ++r) out.record_phases[r] = theta[phase_index(r)];
  }
  return out;
}

}  // namespace vehs::likelihood::detail

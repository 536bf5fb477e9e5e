#include "vehs/likelihood/detail/selection.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "vehs/core/error.hpp"

namespace vehs::likelihood::detail {

void attach_stderrs(Result& res) {
  Model& m = res.model.model;
  m.drift_stderr.clear();
  m.diffusion_stderr.clear();
  for (auto& e : m.effects) e.stderr_.clear();
  std::vector<std::size_t> in_model;
  for (std::size_t i = 0; i < res.parameters.size(); ++i) {
    const ParameterInfo& p = res.parameters[i];
    const double se = std::sqrt(std::max(res.covariance(Eigen::Index(i), Eigen::Index(i)), 0.0));
    res.stderrs[i] = se;
    switch (p.kind) {
      case ParameterKind::Drift:
      case ParameterKind::Diffusion: {
        const std::string term = p.name.substr(p.name.find('[') + 1, p.name.size() - p.name.find('[') - 2);
        (p.kind == ParameterKind::Drift ? m.drift_stderr : m.diffusion_stderr)[term] = se;
        in_model.push_back(i);
        break;
      }
      case ParameterKind::Effect:
        for (auto& e : m.effects)
          if (e.id == p.effect) e.stderr_[p.effect_param] = se;
        in_model.push_back(i);
        break;
      default: break;
    }
  }
  ParameterCovariance& c = m.covariance;
  c.names.clear();
  for (std::size_t i : in_model) c.names.push_back(res.parameters[i].name);
  c.matrix.assign(in_model.size() * in_model.size(), 0.0);
  for (std::size_t a = 0; a < in_model.size(); ++a)
    for (std::size_t b = 0; b < in_model.size(); ++b)
      c(a, b) = res.covariance(Eigen::Index(in_model[a]), Eigen::Index(in_model[b]));
}

double chi2_1_upper_quantile(double p) {
  // P(χ²₁ > q) = erfc(sqrt(q/2)): bisection on z = sqrt(q)
  double lo = 0.0, hi = 40.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
  }
  const double z = 0.5 * (lo + hi);
  return z * z;
}

namespace {

/// The linear stiffness x and damping y beside an electromechanical state: −κv acts as a damping
/// κ/λ when λ ≫ ω and as a stiffness when λ ≪ ω, so without y (or x) the state takes its place
/// along that ridge — an outside tester's coupled bistable (β 0.1): y removed at 2ΔlogL under
/// the threshold, the coupling written 6.6 SE and λ 4.1 SE from the truth, diagnosed adequate.
bool hidden_state_stand_in(const Model& m, const Term& t) {
  return m.find_effect(EffectId::ElectromechanicalCoupling) && t.is_polynomial() &&
         ((t.px == 1 && t.py == 0) || (t.px == 0 && t.py == 1));
}

bool kept(const ParameterInfo& p, const RefineOptions& o, const Model& m) {
  if (p.kind == ParameterKind::MeasurementSd) return false;
  if (p.kind != ParameterKind::Drift && p.kind != ParameterKind::Diffusion) return true;
  if (p.log_scale) return true;  // diffusion[1]
  const TermList& list = p.kind == ParameterKind::Drift ? m.drift : m.diffusion;
  const std::vector<Term>& keep = p.kind == ParameterKind::Drift ? o.keep_drift : o.keep_diffusion;
  // the p.index-th non-zero term of the list
  int k = -1;
  for (const auto& tc : list) {
    if (tc.coef == 0.0) continue;
    if (++k == p.index)
      return std::find(keep.begin(), keep.end(), tc.term) != keep.end() ||
             (p.kind == ParameterKind::Drift && hidden_state_stand_in(m, tc.term));
  }
  return true;
}

/// The model without parameter `p` (a term's coefficient set to 0, or no measurement noise).
ObservedModel without(const ObservedModel& m, const ParameterInfo& p, FitChoice& choice) {
  ObservedModel out = m;
  if (p.kind == ParameterKind::MeasurementSd) {
    out.measurement_sd = 0.0;
    choice.fit_measurement_noise = false;
    return out;
  }
  TermList& list = p.kind == ParameterKind::Drift ? out.model.drift : out.model.diffusion;
  int k = -1;
  for (auto it = list.begin(); it != list.end(); ++it) {
    if (it->coef == 0.0) continue;
    if (++k == p.index) {
      list.erase(it);
      break;
    }
  }
  return out;
}

double removal_threshold(const ParameterInfo& p, const RefineOptions& o, double n) {
  if (o.criterion == SelectionCriterion::Bic) return std::log(n);
  const bool boundary = p.kind == ParameterKind::MeasurementSd;
  return chi2_1_upper_quantile(boundary ? 2.0 * o.lr_alpha : o.lr_alpha);
}

double wald_z(const Result& r, std::size_t i) {
  return r.stderrs[i] > 0.0 ? std::abs(r.values[i]) / r.stderrs[i] : 0.0;
}

/// Parameters removed together by remove_block: |z| below this.
constexpr double kBlockZ = 2.0;

/// The model without every parameter of `block` (indices into r.parameters): within a list the
/// later terms first, so that the earlier ones' indices stay valid.
ObservedModel without_all(const Result& r, std::vector<std::size_t> block, FitChoice& choice) {
  std::sort(block.begin(), block.end(), [&](std::size_t a, std::size_t b) {
    return r.parameters[a].index > r.parameters[b].index;
  });
  ObservedModel out = r.model;
  for (std::size_t i : block) out = without(out, r.parameters[i], choice);
  return out;
}

/// One refit without every removable parameter with |z| < kBlockZ (at least two): true, with
/// `current` and `choice` replaced and the steps logged, when their joint 2ΔlogL is below the
/// smallest of their thresholds.
bool remove_block(Result& current, FitChoice& choice, const Dataset& data, const RefineOptions& o,
                  const RefineOptions& near, std::vector<SelectionStep>& steps) {
  const double n = double(current.summary.observations);
  std::vector<std::size_t> block;
  double threshold = INFINITY;
  for (std::size_t i = 0; i < current.parameters.size(); ++i)
    if (!kept(current.parameters[i], o, current.model.model) && wald_z(current, i) < kBlockZ) {
      block.push_back(i);
      threshold = std::min(threshold, removal_threshold(current.parameters[i], o, n));
    }
  if (block.size() < 2) return false;
  FitChoice reduced_choice = choice;
  Result r;
  try {
    r = fit_support(without_all(current, block, reduced_choice), data, near, reduced_choice, false);
  } catch (const Error&) {
    return false;  // one at a time then finds the term that cannot go
  }
  const double delta = 2.0 * (current.log_likelihood - r.log_likelihood);
  const bool accepted = delta < threshold;
  if (o.log) {
    char line[200];
    std::snprintf(line, sizeof line, "likelihood selection: remove the %zu terms with |z| < %g together: 2 dlogL %.4g vs %.4g: %s",
                  block.size(), kBlockZ, delta, threshold, accepted ? "removed" : "one at a time");
    o.log(line);
  }
  if (!accepted) return false;
  for (std::size_t i : block) {
    SelectionStep st;
    st.removed = current.parameters[i].name;
    st.z = wald_z(current, i);
    st.log_likelihood = r.log_likelihood;
    st.delta = delta;
    st.threshold = threshold;
    st.accepted = true;
    st.together = int(block.size());
    steps.push_back(st);
  }
  current = std::move(r);
  choice = reduced_choice;
  return true;
}

void log_removal(const RefineOptions& o, const SelectionStep& st) {
  if (!o.log) return;
  char line[256];
  std::snprintf(line, sizeof line, "likelihood selection: remove %s (|z| %.3g): 2 dlogL %.4g%s vs %.4g: %s", st.removed.c_str(),
                st.z, st.delta, st.by_wald ? " (Wald z², no refit)" : "", st.threshold, st.accepted ? "removed" : "kept");
  o.log(line);
}

}  // namespace

Result select_support(const ObservedModel& start, const Dataset& data, const RefineOptions& o,
                      FitChoice choice) {
  Result current = fit_support(start, data, o, choice, false);
  // refits start at the previous optimum: no warm start on a subsample
  RefineOptions near = o;
  near.warm_start_samples = std::numeric_limits<std::size_t>::max();
  std::vector<SelectionStep> steps;
  if (!o.candidate_drift.empty() || !o.candidate_diffusion.empty()) current = add_terms(std::move(current), data, near, choice, steps);
  const double n = double(current.summary.observations);
  remove_block(current, choice, data, o, near, steps);
  std::vector<std::string> unremovable;  // terms whose reduced model the filter cannot start
  for (;;) {
    int best = -1;
    double best_z = 0.0;
    for (std::size_t i = 0; i < current.parameters.size(); ++i) {
      const ParameterInfo& p = current.parameters[i];
      if (kept(p, o, current.model.model)) continue;
      if (std::find(unremovable.begin(), unremovable.end(), p.name) != unremovable.end()) continue;
      const double z = wald_z(current, i);
      if (best < 0 || z < best_z) {
        best = int(i);
        best_z = z;
      }
    }
    if (best < 0) break;
    const ParameterInfo& p = current.parameters[std::size_t(best)];
    SelectionStep st;
    st.removed = p.name;
    st.z = best_z;
    st.threshold = removal_threshold(p, o, n);
    if (best_z * best_z > kWaldKeepFactor * st.threshold) {
      st.delta = best_z * best_z;
      st.log_likelihood = current.log_likelihood;
      st.by_wald = true;
      log_removal(o, st);
      steps.push_back(st);
      break;
    }
    FitChoice reduced_choice = choice;
    const ObservedModel reduced = without(current.model, p, reduced_choice);
    Result r;
    try {
      r = fit_support(reduced, data, near, reduced_choice, false);
    } catch (const Error& e) {
      // e.g. removing a damping term leaves a model that is unstable at the data: keep it
      st.delta = INFINITY;
      st.threshold = 0.0;
      st.accepted = false;
      if (o.log) o.log("likelihood selection: cannot remove " + p.name + " (" + e.what() + ")");
      steps.push_back(st);
      unremovable.push_back(p.name);
      continue;
    }
    st.log_likelihood = r.log_likelihood;
    st.delta = 2.0 * (current.log_likelihood - r.log_likelihood);
    st.accepted = st.delta < st.threshold;
    log_removal(o, st);
    steps.push_back(st);
    if (!st.accepted) break;
    current = std::move(r);
    choice = reduced_choice;
  }
  // final fit with the requested covariance
  Result final = fit_support(current.model, data, near, choice, true);
  final.summary.selection = steps;
  return final;
}

}  // namespace vehs::likelihood::detail

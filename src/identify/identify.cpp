// identify(): options, the dispatch to the term fit or the dynamic-effect fits, and the
// physical parameters of term-like effects. The method is described in identify.hpp; the passes
// live in term_fit.cpp and the files it includes, the dynamic effects in profile_fit.cpp and
// colored_fit.cpp.
#include "vehs/identify/identify.hpp"

#include <algorithm>
#include <cmath>

#include "colored_fit.hpp"
#include "physical_units.hpp"
#include "profile_fit.hpp"
#include "term_fit.hpp"
#include "vehs/core/error.hpp"
#include "vehs/core/standard_errors.hpp"
#include "vehs/identify/dynamic.hpp"

namespace vehs::identify {

namespace {
/// Standard errors of ρ_k − ρ_3k above 0 that refute an explicit scheme (white residuals: √(2/rows)).
constexpr double kSchemeRefuted = 5.0;
}  // namespace

SamplingRule sampling_rule(double rho_k, double rho_2k, double rho_3k, double rows) {
  SamplingRule r;
  r.noise_share = std::clamp(6.0 * (rho_2k - rho_3k), 0.0, 1.0);
  const double se = 6.0 * std::sqrt(2.0 / std::max(rows, 1.0));
  r.noisy = r.noise_share > std::max(0.05, 3.0 * se);
  const double eta = r.noisy ? r.noise_share : 0.0;
  r.continuous = (rho_k - rho_3k) + (2.0 / 3.0) * eta > (1.0 - eta) / 8.0;
  if (!r.continuous && rho_k - rho_3k > kSchemeRefuted * std::sqrt(2.0 / std::max(rows, 1.0))) {
    // lag k clearly ABOVE the lag-3k reference: no explicit scheme gives that at any noise share
    // (its lag-k base is 0, noise and coarse dynamics only lower it), a sensor on a continuous
    // process with white noise does, 1/4 − (11/12)η; η by GLS of (d_k − 1/4, d_2k) = (−11/12, 1/6)·η
    const double a1 = -11.0 / 12.0, a2 = 1.0 / 6.0, d1 = rho_k - rho_3k - 0.25, d2 = rho_2k - rho_3k;
    const double info = (2 * a1 * a1 - 2 * a1 * a2 + 2 * a2 * a2) / 3.0;  // per row
    const double eta_c = std::clamp((2 * a1 * d1 - a1 * d2 - a2 * d1 + 2 * a2 * d2) / 3.0 / info, 0.0, 1.0);
    r.continuous = true;
    r.noisy = eta_c > std::max(0.05, 3.0 / std::sqrt(info * std::max(rows, 1.0)));
    r.noise_share = eta_c;
  }
  if (!r.continuous) {
    // scheme-consistent: GLS of (d_k, d_2k) = (−2/3, 1/6)·η, covariance [[2, 1], [1, 2]]/rows
    // (inverse ∝ [[2, −1], [−1, 2]]); information aᵀΣ⁻¹a = (7/18)·rows
    const double a1 = -2.0 / 3.0, a2 = 1.0 / 6.0, d1 = rho_k - rho_3k, d2 = rho_2k - rho_3k;
    const double info = (2 * a1 * a1 - 2 * a1 * a2 + 2 * a2 * a2) / 3.0;  // per row
    // both readings must find the noise: lag k confirms (or refutes) a lag-2k excess, but it
    // never adds noise on its own (coarsely sampled dynamics also push lag k below 0)
    const double eta_s = std::clamp((2 * a1 * d1 - a1 * d2 - a2 * d1 + 2 * a2 * d2) / 3.0 / info, 0.0, 1.0);
    r.noisy = r.noisy && eta_s > std::max(0.05, 3.0 / std::sqrt(info * std::max(rows, 1.0)));
    r.noise_share = r.noisy ? eta_s : std::min(r.noise_share, eta_s);
  }
  r.verdict = r.noisy        ? SamplingVerdict::Noisy
              : r.continuous ? SamplingVerdict::ContinuousTime
                             : SamplingVerdict::SchemeConsistent;
  return r;
}

std::string Options::invalid_reason() const {
  if (drift_library.empty() && effects.empty()) return "the drift library is empty";
  if (diffusion_library.empty()) return "the diffusion library is empty";
  for (const auto& t : diffusion_library)
    if (!allowed_in_diffusion(t))
      return "diffusion term '" + t.name() + "' is not allowed";
  if (stride < 0) return "stride must be >= 0";
  if (stride > 0 && (estimator == Estimator::Paper || estimator == Estimator::Forward))
    return "stride applies to the uli and noisy estimators only";
  if (folds < 1) return "folds must be >= 1";
  if (folds < 2 && sparsity == Sparsity::Ssr && criterion != Criterion::Bic)
    return "cross-validation needs folds >= 2 (or use criterion bic)";
  if (!(stlsq_threshold >= 0.0)) return "stlsq_threshold must be >= 0";
  if (pilot_samples < 1000) return "pilot_samples must be >= 1000";
  if (!(noise_share_target > 0.0 && noise_share_target < 1.0))
    return "noise_share_target must be in (0, 1)";
  for (const auto& e : effects)
    if (!effect_spec(e.id).term_like && !dynamic_fit_supported(e.id))
      return "effect '" + e.name() +
             "' is a dynamic effect whose identification is not supported yet";
  for (const auto& u : user_effects) {
    if (auto why = u.invalid_reason(); !why.empty()) return why;
    for (const auto& e : effects)
      if (e.name() == u.name) return "effect '" + u.name + "' is listed twice";
    for (const auto& v : user_effects)
      if (&v != &u && v.name == u.name) return "user effect '" + u.name + "' is listed twice";
  }
  if (known_force && !effects.empty())
    for (const auto& e : effects)
      if (!effect_spec(e.id).term_like) return "known_force cannot be combined with dynamic effects";
  return "";
}

std::vector<Effect> effect_parameters(const Model& model, const std::vector<Effect>& effects) {
  std::vector<Effect> out;
  for (const auto& e : effects) {
    Effect fitted;
    fitted.id = e.id;
    for (const auto& ps : effect_spec(e.id).params) {
      Effect unit;
      unit.id = e.id;
      unit.params[std::string(ps.name)] = 1.0;
      const EffectTerms t = effect_terms(unit);
      const TermList& list = t.drift.empty() ? t.diffusion : t.drift;
      if (list.size() != 1) continue;
      const bool diffusion = t.drift.empty();
      const double per_unit = list[0].coef;  // term coefficient per unit of the parameter
      const double coef = coefficient(diffusion ? model.diffusion : model.drift, list[0].term);
      fitted.params[std::string(ps.name)] = coef / per_unit;
      const auto& semap = diffusion ? model.diffusion_stderr : model.drift_stderr;
      if (auto it = semap.find(list[0].term.name()); it != semap.end()) fitted.stderr_[std::string(ps.name)] = it->second;
    }
    out.push_back(std::move(fitted));
  }
  return out;
}

EffectTerms kept_terms(const Options& options) {
  EffectTerms kept;
  for (const Term& t : options.keep_drift) kept.drift.push_back({t, 1.0});
  for (const Term& t : options.keep_diffusion) kept.diffusion.push_back({t, 1.0});
  std::vector<EffectTerms> parts;
  for (const Effect& e : options.effects) parts.push_back(unit_effect_terms(e.id));
  for (const UserEffect& u : options.user_effects) parts.push_back(u.unit_terms());
  for (const EffectTerms& p : parts) {
    kept.drift.insert(kept.drift.end(), p.drift.begin(), p.drift.end());
    kept.diffusion.insert(kept.diffusion.end(), p.diffusion.begin(), p.diffusion.end());
  }
  return kept;
}

namespace {

/// The user effects' terms added to the dictionaries and kept through selection.
Options with_user_terms(const Options& options) {
  Options o = options;
  for (const UserEffect& u : options.user_effects)
    for (const UserEffectParam& p : u.params) {
      std::vector<Term>& library = p.diffusion ? o.diffusion_library : o.drift_library;
      if (std::find(library.begin(), library.end(), p.term) == library.end()) library.push_back(p.term);
      (p.diffusion ? o.keep_diffusion : o.keep_drift).push_back(p.term);
    }
  o.user_effects.clear();
  return o;
}

// White sensor noise adds its variance to x's: an estimate above var(x) is not a noise level but
// a sign of data the model of the sampling does not describe (glitches, a wrong column).
void check_sensor_noise(const Result& r, const Dataset& data) {
  if (!r.model.fit) return;
  const double sd = r.model.fit->sampling.sensor_noise_sd;
  const double var = pooled_record_variance(data);
  if (sd > 0.0 && sd * sd > var)
    throw Error("identify: the sensor-noise estimate (sd " + std::to_string(sd) +
                ") exceeds the spread of x itself (sd " + std::to_string(std::sqrt(var)) +
                "): the data are not samples of a continuous signal plus white noise (glitches? a wrong column?)");
}

Result dispatch(const Dataset& data, const Options& options) {
  for (const auto& e : options.effects)
    if (e.id == EffectId::ColoredNoise) return detail::identify_colored(data, options);
  for (const auto& e : options.effects)
    if (is_dynamic(e.id)) return detail::identify_profile(data, options);
  return detail::identify_terms(data, options);
}

}  // namespace

Result identify(const Dataset& data, const Options& requested) {
  if (auto why = requested.invalid_reason(); !why.empty()) throw Error("identify: " + why);
  const Options options = with_user_terms(requested);
  if (options.known_force)
    require(options.known_force->size() == data.x.size(), "identify: known_force must have one value per sample");
  const Scales s = natural_scales(data);
  Result r;
  if (s.is_identity()) {
    r = dispatch(data, options);
  } else {
    std::vector<double> force;
    const Options internal = detail::options_in_internal_units(options, s, force);
    r = detail::result_in_physical_units(dispatch(to_internal(data, s), internal), s);
  }
  check_sensor_noise(r, data);
  detail::require_finite_standard_errors(r.model);
  standard_errors_from_covariance(r.model, "identify");
  for (const UserEffect& u : requested.user_effects) r.report.user_effect_params.push_back(user_effect_fit(r.model, u));
  return r;
}

}  // namespace vehs::identify

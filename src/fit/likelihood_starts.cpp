#include "vehs/fit/likelihood_starts.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "vehs/core/detail/format.hpp"
#include "vehs/core/error.hpp"
#include "vehs/likelihood/detail/data_share.hpp"

namespace vehs {

namespace {

double sensor_noise(const Model& m) { return m.fit ? m.fit->sampling.sensor_noise_sd : 0.0; }

bool same_terms(const TermList& a, const TermList& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!(a[i].term == b[i].term) || a[i].coef != b[i].coef) return false;
  return true;
}

/// Same coefficients, effects and sensor noise: the same start.
bool same_fit(const Model& a, const Model& b) {
  if (!same_terms(a.drift, b.drift) || !same_terms(a.diffusion, b.diffusion) || sensor_noise(a) != sensor_noise(b) ||
      a.effects.size() != b.effects.size())
    return false;
  for (std::size_t i = 0; i < a.effects.size(); ++i)
    if (a.effects[i].id != b.effects[i].id || a.effects[i].params != b.effects[i].params) return false;
  return true;
}

std::string g(double v, int digits = 10) { return vehs::detail::format_number(v, digits); }

}  // namespace

std::vector<LikelihoodStart> likelihood_starts(const std::vector<MomentCandidate>& candidates,
                                               bool estimate_measurement_noise) {
  std::vector<LikelihoodStart> out;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const MomentCandidate& c = candidates[i];
    LikelihoodStart s;
    s.name = i == 0 ? "auto: " + c.estimator : c.estimator;
    s.candidate = i;
    if (!c.model) {
      s.status = "failed: " + c.failure;
      out.push_back(s);
      continue;
    }
    for (std::size_t j = 0; j < i && s.status.empty(); ++j)
      if (candidates[j].model && same_fit(*c.model, *candidates[j].model))
        s.status = "same as " + (j == 0 ? "auto: " + candidates[j].estimator : candidates[j].estimator);
    s.measurement_sd = sensor_noise(*c.model);
    out.push_back(s);
    if (s.status.empty() && s.measurement_sd > 0.0 && estimate_measurement_noise) {
      s.name += " (measurement_sd scanned)";
      s.measurement_sd = 0.0;
      out.push_back(s);
    }
  }
  return out;
}

likelihood::RefineOptions brief_options(const likelihood::RefineOptions& options) {
  likelihood::RefineOptions brief = options;
  brief.select = false;
  brief.bias_correction_datasets = 0;
  brief.bias_correction_auto = false;
  brief.covariance = likelihood::Covariance::Fisher;
  brief.max_rounds = std::min(options.max_rounds, kBriefRounds);
  brief.log = {};
  return brief;
}

Dataset brief_share(const Dataset& data) {
  const std::size_t n = data.total_samples();
  return n > kBriefSamples ? likelihood::detail::warm_start_share(data, double(kBriefSamples) / double(n), false) : data;
}

std::optional<likelihood::ObservedModel> best_start(std::vector<LikelihoodStart>& starts,
                                                    const std::vector<MomentCandidate>& candidates,
                                                    const Dataset& data, const likelihood::RefineOptions& options,
                                                    const std::function<void()>& fitted) {
  const likelihood::RefineOptions brief = brief_options(options);
  const Dataset on = brief_share(data);
  std::optional<likelihood::ObservedModel> best;
  LikelihoodStart* chosen = nullptr;
  for (LikelihoodStart& s : starts) {
    if (!s.status.empty()) continue;
    const auto t0 = std::chrono::steady_clock::now();
    try {
      const likelihood::ObservedModel start{*candidates[s.candidate].model, s.measurement_sd, {}};
      likelihood::Result r = likelihood::refine(start, on, brief);
      s.log_likelihood = r.log_likelihood;
      s.status = "fitted";
      if (!chosen || r.log_likelihood > chosen->log_likelihood) chosen = &s, best = std::move(r.model);
    } catch (const Error& e) {
      s.status = std::string("failed: ") + e.what();
    }
    s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (fitted) fitted();
  }
  if (chosen) chosen->status = "chosen";
  if (options.log)
    for (const LikelihoodStart& s : starts)
      options.log("likelihood start " + s.name + ": " +
                  (std::isfinite(s.log_likelihood) ? "log L " + g(s.log_likelihood) + " on " + std::to_string(on.total_samples()) +
                                                         " samples after " + std::to_string(brief.max_rounds) + " rounds (" +
                                                         g(s.seconds, 3) + " s), "
                                                   : std::string()) +
                  s.status);
  return best;
}

}  // namespace vehs

#pragma once
// One run of the score-test suspects on a hidden-effect case (score_fixtures.hpp) and the oracle
// beside it, shared by the CI tests (test_score_suspects.cpp) and the study (test_score_study.cpp).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "vehs/core/error.hpp"
#include "vehs/diagnose/score_suspects.hpp"
#include "vehs/identify/identify.hpp"
#include "vehs/likelihood/refine.hpp"

#include "score_fixtures.hpp"

namespace score_test {

inline std::string describe(const vehs::diagnose::ScoreSuspectReport& r) {
  std::string s = r.note;
  for (const auto& sp : r.ranked) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "\n   %s: stat %.3g p %.3g z %.2f power %.2f (%.1f s)", sp.effect.c_str(),
                  sp.statistic, sp.p_value, sp.z, sp.power, sp.seconds);
    s += buf;
    if (const auto at = sp.test.find("; look-alikes"); at != std::string::npos) s += " [" + sp.test.substr(at + 2) + "]";
    for (const auto& [k, v] : sp.params) {
      auto it = sp.params_stderr.find(k);
      s += " " + k + "=" + std::to_string(v) + (it != sp.params_stderr.end() ? "±" + std::to_string(it->second) : "");
    }
  }
  for (const auto& [e, why] : r.untested) s += "\n   untested " + e + ": " + why;
  return s;
}

/// The oracle: the z of the hidden effect's parameter when the likelihood is given the effect
/// (refined from the truth on all the data).
inline double oracle_z(const HiddenCase& hc, const vehs::Dataset& d) {
  vehs::likelihood::ObservedModel start{truth_of(hc), 0.0, {}};
  vehs::likelihood::RefineOptions o;
  o.estimate_measurement_noise = hc.sensor_noise_share > 0.0;
  o.per_record_phase = hc.phase_per_record;
  const vehs::likelihood::Result r = vehs::likelihood::refine(start, d, o);
  const int i = r.find(oracle_parameter(hc));
  if (i < 0) throw vehs::Error("oracle: no parameter " + oracle_parameter(hc));
  return std::abs(r.values[std::size_t(i)] / r.stderrs[std::size_t(i)]);
}

/// The baseline identify fits and its score suspects (wall time). With sensor noise (the coarse
/// shape) the baseline is refined by the likelihood with its measurement noise, as identify-vehs
/// does at coarse sampling.
struct Outcome {
  vehs::Model baseline;
  double measurement_sd = 0.0;
  vehs::diagnose::ScoreSuspectReport report;
  double seconds = 0.0;
};

inline Outcome run_case(const HiddenCase& hc, const vehs::Dataset& d,
                        const vehs::diagnose::ScoreSuspectOptions& options = {}) {
  Outcome o;
  o.baseline = vehs::identify::identify(d, baseline_options_for(hc)).model;
  if (hc.sensor_noise_share > 0.0) {
    vehs::likelihood::RefineOptions ro;
    ro.estimate_measurement_noise = true;
    const vehs::likelihood::Result r = vehs::likelihood::refine({o.baseline, 0.0, {}}, d, ro);
    vehs::FitInfo fit = o.baseline.fit ? *o.baseline.fit : vehs::FitInfo{};
    fit.likelihood = vehs::LikelihoodFit{};
    fit.likelihood->measurement_sd = o.measurement_sd = r.model.measurement_sd;
    o.baseline = r.model.model;
    o.baseline.fit = fit;
  }
  const auto t0 = std::chrono::steady_clock::now();
  o.report = vehs::diagnose::score_suspects(o.baseline, d, o.measurement_sd, options);
  o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return o;
}

inline const HiddenCase& case_named(const std::string& name) {
  static const std::vector<HiddenCase> all = hidden_cases();
  for (const auto& c : all)
    if (c.name == name) return c;
  throw vehs::Error("no hidden case " + name);
}

}  // namespace score_test

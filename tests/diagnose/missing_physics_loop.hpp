#pragma once
// The missing-physics loop of issue 7 shared by the tests of term-like and dynamic effects:
// data with a hidden effect, a baseline of the paper's model form fitted by identify (the code
// under test never sees the truth), diagnose, the refit with the suspect added, diagnose again.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <string>

#include "diagnose_fixtures.hpp"
#include "vehs/io/model_file.hpp"

namespace diag_test::loop {

using vehs::diagnose::Result;

/// The paper's Eq. 7 form for a potential with odd powers up to x^3: b2 = −βy − k1 x − k3 x³,
/// a22 = 2D + 2Q x².
inline const std::vector<std::string> kBaselineDrift{"x", "x^3", "y"};
inline const std::vector<std::string> kBaselineDiffusion{"1", "x^2"};

inline vehs::Model monostable() {  // hardening Duffing, one well at 0
  return model_of(R"({"drift": {"x": -1.0, "x^3": -0.5, "y": -0.1},
                      "diffusion": {"1": 0.02, "x^2": 0.01}})");
}

/// The same harvester under stronger excitation (2D = two_d): velocities large enough for the
/// velocity-dependent forces and noise to matter.
inline vehs::Model excited(vehs::Model m, double two_d) {
  for (auto& tc : m.diffusion)
    if (tc.term.name() == "1") tc.coef = two_d;
  return m;
}

inline std::string describe(const Result& r) {
  std::string s = vehs::enum_to_string(vehs::diagnose::kVerdictNames, r.verdict) + " score " +
                  std::to_string(r.score) + ":";
  for (const auto& c : r.components)
    s += " " + c.name + " p=" + (c.test.available ? std::to_string(c.test.p_value) : "n/a") +
         (c.name == "residual_lines" ? " (" + c.test.method + ")" : "");
  s += " | suspects:";
  for (const auto& sp : r.suspects.ranked)
    s += " " + sp.effect + " " + std::to_string(sp.evidence) + " (z " + std::to_string(sp.z) + ", " +
         params_text(sp.params) + ")";
  for (const auto& [e, why] : r.suspects.untested) s += " | untested " + e + ": " + why;
  if (!r.suspects.note.empty()) s += " | note: " + r.suspects.note;
  s += " | seconds:";
  s += timings_text(r);
  return s;
}

/// 64 records of `samples` samples at Δt = 0.02 (a sensor sampling a continuous process: 10
/// Itô–Taylor substeps per sample); VEHS_MP_RECORDS / VEHS_MP_SAMPLES override (exploration).
inline DataSpec continuous_spec(std::uint64_t seed, std::size_t samples = 6000) {
  DataSpec s;
  s.records = std::getenv("VEHS_MP_RECORDS") ? std::atoi(std::getenv("VEHS_MP_RECORDS")) : 64;
  s.samples = std::getenv("VEHS_MP_SAMPLES") ? std::strtoull(std::getenv("VEHS_MP_SAMPLES"), nullptr, 10) : samples;
  s.dt = 0.02;
  s.substeps = 10;
  s.scheme = vehs::sim::Scheme::Taylor15;
  s.seed = seed;
  return s;
}

inline vehs::diagnose::Options options(std::uint64_t seed) {
  auto o = fast_options(seed);
  o.fpk = false;
  return o;
}

inline vehs::Model fit_with(const vehs::Dataset& d, const std::vector<vehs::Effect>& effects) {
  vehs::identify::Options o;
  o.drift_library.clear();
  o.diffusion_library.clear();
  for (const auto& t : kBaselineDrift) o.drift_library.push_back(vehs::Term::parse(t));
  for (const auto& t : kBaselineDiffusion) o.diffusion_library.push_back(vehs::Term::parse(t));
  o.sparsity = vehs::identify::Sparsity::None;
  o.effects = effects;
  return vehs::identify::identify(d, o).model;
}

struct Hidden {
  vehs::Effect effect;  ///< with the true parameters
  vehs::Model base;     ///< the potential
};

/// What one loop found (for the exploration over random draws).
struct LoopOutcome {
  bool ok = true;               ///< every check of the loop held
  std::string heldout_leader;   ///< the suspect with the largest held-out evidence
  std::string named_first;      ///< the suspect diagnose ranked first (after its confirmation)
};

// CHECK that also records the outcome (the expression is evaluated twice: no side effects)
#define VEHS_LOOP_CHECK(...)                                   \
  do {                                                         \
    const bool loop_check_ = static_cast<bool>(__VA_ARGS__);   \
    CHECK(__VA_ARGS__);                                        \
    out.ok = out.ok && loop_check_;                            \
  } while (0)

/// The loop for one hidden effect (parameters the truth sets to zero are checked for 3 SE only).
inline LoopOutcome run_loop(const Hidden& h, std::uint64_t seed, std::size_t samples = 6000, int records = 64) {
  LoopOutcome out;
  vehs::Model truth = h.base;
  if (!vehs::effect_spec(h.effect.id).term_like) truth.effects.push_back(h.effect);
  {
    const auto t = vehs::effect_terms(h.effect);
    for (const auto& tc : t.drift) truth.drift.push_back(tc);
    for (const auto& tc : t.diffusion) truth.diffusion.push_back(tc);
    vehs::canonicalize(truth.drift, "truth drift");
    vehs::canonicalize(truth.diffusion, "truth diffusion");
  }
  DataSpec spec = continuous_spec(seed, samples);
  if (!std::getenv("VEHS_MP_RECORDS")) spec.records = records;
  const auto d = simulate(truth, spec);
  const vehs::Model baseline = fit(d, kBaselineDrift, kBaselineDiffusion);
  INFO("hidden " << vehs::effect_to_json(h.effect).dump() << " seed " << seed);
  INFO("baseline model " << vehs::model_to_json(baseline).dump());
  const Result r0 = vehs::diagnose::diagnose(baseline, d, options(seed));
  INFO("baseline: " << describe(r0));
  tally_result("baseline", r0);
  tally_result_suspects(r0, h.effect.name(), "", 1.0);
  // power checks: over seed shifts the baseline's smallest p-value and the hidden effect's lead
  // in evidence are quoted in bench/results/ (seed-study.sh on "[missing_physics]")
  VEHS_LOOP_CHECK(!r0.adequate());
  REQUIRE_FALSE(r0.suspects.ranked.empty());
  out.named_first = r0.suspects.ranked[0].effect;
  out.heldout_leader = std::max_element(r0.suspects.ranked.begin(), r0.suspects.ranked.end(),
                                        [](const auto& a, const auto& b) { return a.evidence < b.evidence; })
                           ->effect;
  VEHS_LOOP_CHECK(r0.suspects.ranked[0].effect == h.effect.name());
  VEHS_LOOP_CHECK(r0.suspects.ranked[0].significant);
  VEHS_LOOP_CHECK(r0.suspects.ranked[0].effect == h.effect.name());

  // the user's one-line change: add the effect named by the diagnosis
  vehs::Effect added;
  added.id = vehs::enum_from_string(vehs::kEffectNames, r0.suspects.ranked[0].effect, "suspect");
  const vehs::Model refit = fit_with(d, {added});
  nlohmann::json fitted = nlohmann::json::object(), fitted_se = nlohmann::json::object();
  if (vehs::effect_spec(added.id).term_like) {
    const auto ep = vehs::identify::effect_parameters(refit, {added});
    REQUIRE(ep.size() == 1);
    for (const auto& [k, v] : ep[0].params) fitted[k] = v;
    for (const auto& [k, v] : ep[0].stderr_) fitted_se[k] = v;
  } else {
    const vehs::Effect* fe = refit.find_effect(added.id);
    REQUIRE(fe != nullptr);
    for (const auto& [k, v] : fe->params) fitted[k] = v;
    for (const auto& [k, v] : fe->stderr_) fitted_se[k] = v;
  }
  // the fitted parameters: z-checks at z_limit(k) of identify's calibrated standard errors
  // (identify_fixtures.hpp), k the number of parameters; resolved (SE ≤ 15 % of a non-zero truth)
  const int k = static_cast<int>(h.effect.params.size());
  const double zl = 1.15 * vehs_test::z_bound(k);
  for (const auto& [name, value] : h.effect.params) {
    REQUIRE(fitted.contains(name));
    REQUIRE(fitted_se.contains(name));
    const double est = fitted[name].get<double>(), se = fitted_se[name].get<double>();
    INFO(name << ": truth " << value << ", fitted " << est << " ± " << se);
    // a phase is compared modulo 2π
    const double err = name == "phase" ? std::remainder(est - value, 2.0 * M_PI) : est - value;
    vehs_test::tally("refit " + name, err / se, value != 0.0 ? err / std::abs(value) : NAN);
    VEHS_LOOP_CHECK(std::abs(err) <= zl * se);
    if (value != 0.0) VEHS_LOOP_CHECK(se <= 0.15 * std::abs(value));  // 15 % of zero: no test
  }
  // The refit is the true model form: its verdict is a null check, at α = 5e-5 family-wise (the
  // false failure per run if the p-values are valid; the calibration tests measure them at 1 %).
  auto o1 = options(seed + 1000);
  o1.alpha = 5e-5;
  const Result r1 = vehs::diagnose::diagnose(refit, d, o1);
  INFO("refit: " << describe(r1));
  tally_result("refit", r1);
  VEHS_LOOP_CHECK(r1.adequate());
  VEHS_LOOP_CHECK(r1.score <= 0.5 * r0.score);
  if (std::getenv("VEHS_MP_VERBOSE")) std::printf("baseline: %s\nrefit: %s\n", describe(r0).c_str(), describe(r1).c_str());
  for (const auto& sp : r1.suspects.ranked) VEHS_LOOP_CHECK(sp.effect != h.effect.name());
  return out;
}

#undef VEHS_LOOP_CHECK

inline double uniform(std::mt19937_64& g, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(g); }

inline vehs::Effect effect(const std::string& name, std::map<std::string, double> params) {
  vehs::Effect e;
  e.id = vehs::enum_from_string(vehs::kEffectNames, name, "test");
  e.params = std::move(params);
  return e;
}


}  // namespace diag_test::loop

// Suspects for the dynamic effects (impact stops, harmonic forcing, electromechanical
// coupling, coloured OU excitation): data simulated as a sensor samples a continuous process (fine internal steps) with
// the effect hidden, parameters drawn at random within physical ranges by the test; the baseline
// (the potential's own terms) is fitted by identify; rank_suspects must rank the hidden effect
// first and significant. Control data (no hidden effect) give no significant dynamic suspect.
#include <catch2/catch.hpp>

#include <algorithm>
#include <random>
#include <string>

#include "vehs/core/model.hpp"
#include "vehs/diagnose/score_suspects.hpp"
#include "vehs/diagnose/suspects.hpp"
#include "vehs/identify/identify.hpp"
#include "vehs/sim/simulate.hpp"

#include "../identify/identify_fixtures.hpp"
#include "diagnose_fixtures.hpp"

using namespace vehs;
using namespace vehs_test;

namespace {

/// The baseline the user would have: the potential's terms, fitted by identify.
Model baseline_fit(const Dataset& d) { return identify::identify(d, baseline_options()).model; }

diagnose::SuspectReport suspects_of(const Model& base, const Dataset& d) {
  diagnose::Lens lens;
  lens.kinematics = diagnose::Kinematics::Central;
  lens.stride = 1;
  lens.dt = d.common_dt();
  return diagnose::rank_suspects(base, d, lens, diagnose::SuspectOptions{});
}

/// The likelihood's score tests of the effects `base` lacks on the data (up to `max_samples`; 0: all).
diagnose::ScoreSuspectReport score_tests_of(const Model& base, const Dataset& d, double max_samples = 1e5) {
  diagnose::ScoreSuspectOptions so;
  so.max_samples = max_samples;
  return diagnose::score_suspects(base, d, 0.0, so);
}

/// The held-out suspect `effect` in a report (nullptr when it was not tested).
const diagnose::Suspect* find_suspect(const diagnose::SuspectReport& r, const std::string& effect) {
  for (const auto& sp : r.ranked)
    if (sp.effect == effect) return &sp;
  return nullptr;
}

/// The score test of `effect` in a report (nullptr when it was not tested).
const diagnose::ScoreSuspect* find_score(const diagnose::ScoreSuspectReport& r, const std::string& effect) {
  for (const auto& sp : r.ranked)
    if (sp.effect == effect) return &sp;
  return nullptr;
}

std::string describe(const diagnose::SuspectReport& r) {
  std::string s = r.note;
  for (const auto& sp : r.ranked)
    s += " | " + sp.effect + ": evidence " + std::to_string(sp.evidence) + " z " + std::to_string(sp.z) +
         " params " + diag_test::params_text(sp.params);
  for (const auto& [e, why] : r.untested) s += " | untested " + e + ": " + why;
  return s;
}

/// Power checks (the hidden effect ranked first and held-out significant). Over 3–4 seed shifts
/// (scripts/seed-study.sh): first in every shift; held-out z of harmonic forcing 5.7 ± sd 2.1,
/// electromechanical 4.6 ± 0.8, coloured 6.2 ± 1.5. The stops' held-out z is 5.9 ± 3.6 (4
/// shifts): their significance is checked by the score test on all the data instead (below).
void tally_first(const diagnose::SuspectReport& r, const std::string& effect) {
  if (r.ranked.empty()) return;
  tally(effect + " first", r.ranked[0].effect == effect);
  tally(effect + " z", r.ranked[0].z);
  if (r.ranked.size() > 1) tally(effect + " evidence lead", r.ranked[0].evidence - r.ranked[1].evidence);
}

void check_first(const diagnose::SuspectReport& r, const std::string& effect, bool held_out_significance = true) {
  INFO(describe(r));
  tally_first(r, effect);
  REQUIRE_FALSE(r.ranked.empty());
  CHECK(r.ranked[0].effect == effect);
  if (held_out_significance) CHECK(r.ranked[0].held_out_significant);
}

}  // namespace

TEST_CASE("suspects: hidden harmonic forcing is ranked first and significant",
          "[diagnose][suspects][dynamic]") {
  std::mt19937_64 g(seed(71));
  Model truth = hidden_effect_potential("bistable");
  Effect e;
  e.id = EffectId::HarmonicForcing;
  e.params = {{"amplitude", uniform(g, 0.05, 0.12)}, {"omega", uniform(g, 0.6, 2.0)}, {"phase", uniform(g, -3.0, 3.0)}};
  truth.effects = {e};
  const Dataset d = simulate_hidden(truth, 1000 + g() % 1000, 8, 40000);
  const auto r = suspects_of(baseline_fit(d), d);
  check_first(r, "harmonic_forcing");
  tally("omega", r.ranked[0].params.at("omega") / e.param("omega") - 1.0);
  // omega over 4 seed shifts: relative error sd 0.09 % (1 % is 11 sd)
  CHECK(r.ranked[0].params.at("omega") == Approx(e.param("omega")).epsilon(0.01));
}

TEST_CASE("suspects: hidden impact stops are ranked first and significant",
          "[diagnose][suspects][dynamic]") {
  std::mt19937_64 g(seed(72));
  Model truth = hidden_effect_potential("monostable");
  const Effect e = draw_impact_stop(truth, g);  // gaps at a random upper quantile of |x| without stops
  truth.effects = {e};
  const Dataset d = simulate_hidden(truth, 2000 + g() % 1000, 8, 40000);
  const Model base = baseline_fit(d);
  const auto r = suspects_of(base, d);
  // Over 4 seed shifts: held-out first 4 of 4 with an evidence lead of 1734 ± sd 393 nats (4.4 sd
  // from 0), held-out z 5.9 ± 3.6 (z > 3 failed 1 in 4: the former KNOWN WEAKNESS). The score
  // test on all the data (10^5 samples) names the stops first with z 45 ± 17, ahead of the
  // runner-up by 25 ± 5.6; a claim needs z ≈ 3.8 (alpha 0.01 over 10 effects, 6 gaps), and the
  // lead bounds the z from below: P(lead < 3.8) = Φ(−3.8) = 7e-5, P(held-out lead < 0) = 5e-6
  // (normal spreads): ≤ 1e-4 in all.
  const auto sr = score_tests_of(base, d);
  REQUIRE(sr.ranked.size() > 1);
  tally("impact score z", sr.ranked[0].z);
  tally("impact score lead", sr.ranked[0].z - sr.ranked[1].z);
  check_first(r, "impact_stop", false);
  CHECK(sr.ranked[0].effect == "impact_stop");
  CHECK(sr.ranked[0].significant);
}

TEST_CASE("suspects: a hidden electromechanical state is ranked first and significant",
          "[diagnose][suspects][dynamic]") {
  std::mt19937_64 g(seed(73));
  Model truth = hidden_effect_potential("bistable");
  Effect e;
  e.id = EffectId::ElectromechanicalCoupling;
  e.params = {{"lambda", uniform(g, 0.6, 1.4)}, {"coupling", uniform(g, 0.3, 0.6)}};
  truth.effects = {e};
  // weakly identifiable against damping (see tests/identify/test_dynamic.cpp): 4x the records
  const Dataset d = simulate_hidden(truth, 3000 + g() % 1000, 32, 40000);
  const auto r = suspects_of(baseline_fit(d), d);
  check_first(r, "electromechanical_coupling");
}

TEST_CASE("suspects: control data without a hidden effect give no significant dynamic suspect",
          "[diagnose][suspects][dynamic]") {
  const std::string pot = GENERATE(std::string("bistable"), std::string("monostable"));
  const Model truth = hidden_effect_potential(pot);
  const Dataset d = simulate_hidden(truth, pot == "bistable" ? 4001 : 4002, 8, 40000);
  const auto r = suspects_of(baseline_fit(d), d);
  INFO(pot << ": " << describe(r));
  // Null checks: 4 dynamic effects × 2 potentials, each a one-sided block z of ≥ 20 blocks (at
  // worst Student t₁₉): at the default z > 3 a claim has 3.6e-3 per effect (2.9e-2 per run);
  // here no z above t_bound(16, 19) (one-sided 8 tests at 1e-4 in all).
  for (const auto& sp : r.ranked)
    if (sp.effect == "impact_stop" || sp.effect == "harmonic_forcing" || sp.effect == "electromechanical_coupling" ||
        sp.effect == "colored_noise") {
      vehs_test::tally(pot + " " + sp.effect + " z", sp.z);
      CHECK_FALSE((sp.z > vehs_test::t_bound(16, 19.0) && sp.evidence > 0));
    }
}

namespace {

/// Data with a hidden OU excitation of time constant `tau` and `intensity` on the `pot` potential
/// (8 records × 40000 samples), the baseline identify fits and its held-out suspects.
struct ColouredCase {
  Model truth, base;
  Dataset data;
  diagnose::SuspectReport held_out;
};

ColouredCase coloured_case(const std::string& pot, double tau, double intensity, std::uint64_t data_seed) {
  ColouredCase c;
  c.truth = hidden_effect_potential(pot);
  Effect e;
  e.id = EffectId::ColoredNoise;
  e.params = {{"tau", tau}, {"intensity", intensity}};
  c.truth.effects = {e};
  c.data = simulate_hidden(c.truth, data_seed, 8, 40000);
  c.base = baseline_fit(c.data);
  c.held_out = suspects_of(c.base, c.data);
  return c;
}

}  // namespace

TEST_CASE("suspects: a hidden OU (coloured) excitation is ranked first and significant",
          "[diagnose][suspects][dynamic]") {
  const std::string pot = GENERATE(std::string("bistable"), std::string("monostable"));
  std::mt19937_64 g(seed(pot == "bistable" ? 74 : 75));
  const double tau = uniform(g, 0.2, 1.0), intensity = uniform(g, 0.02, 0.06);
  const ColouredCase c = coloured_case(pot, tau, intensity, 6000 + g() % 1000);
  const auto& r = c.held_out;
  INFO(describe(r));
  tally_first(r, "colored_noise");
  REQUIRE_FALSE(r.ranked.empty());
  // Ranked first by either of diagnose's two rankings of the suspects and significant: by the
  // held-out gain (first, z > 3), or when that falls short by the likelihood's score tests on
  // all the data (computed only then): first there, or first held out, and colored_noise's own
  // score test significant. Over 10 + 10 seed shifts (scripts/seed-study.sh 10
  // build/tests/test_diagnose "suspects: a hidden OU*") the held-out test was first every time
  // with z 6.1 ± sd 1.6, min 3.8, but it falls short at weak draws (the former flake, ≈ 2 % per
  // run). At the weakest corner of the drawn range
  // (intensity 0.02, tau 1.0; tau 0.2 is far stronger), over 14 seed shifts
  // (scripts/seed-study.sh 14 build/tests/test_diagnose "[coloured_corner]"), bistable /
  // monostable: held out first in 12 / 7 of 14 with z 2.2 ± 1.1 / 2.9 ± 1.1; the score tests
  // first in 14 / 14, colored_noise's z above the claim's (≈ 3.1: α = 0.01 over the tested
  // effects, Bonferroni over the τ grid) by 8.6 ± 1.4 / 11.0 ± 1.5 (min 5.7: significance fails
  // with ≤ 1e-9 there, 6 sd), ahead of the runner-up (electromechanical_coupling) by 4.5 ± 0.9
  // / 1.0 ± 0.5 (min 0.35). The monostable lead is the weak point: a normal fit puts it below 0
  // for ≈ 3 % of corner runs, of which half are not first held out either (≈ 1.5 % at the
  // corner itself, far less over the drawn range: 0 of 20 random draws missed held out), so
  // "first" at ≤ 1e-4 per run is not established (KNOWN WEAKNESS: the two hidden states look
  // alike to both tests at the weakest excitation).
  bool first = r.ranked[0].effect == "colored_noise", significant = first && r.ranked[0].held_out_significant;
  if (!significant) {
    const auto sr = score_tests_of(c.base, c.data, 0.0);
    const auto* score = find_score(sr, "colored_noise");
    REQUIRE(score);
    UNSCOPED_INFO("held-out: " << r.ranked[0].effect << " first, z " << r.ranked[0].z << "; score tests: "
                               << sr.ranked[0].effect << " first, colored_noise z " << score->z);
    first = first || sr.ranked[0].effect == "colored_noise";
    significant = score->significant;
  }
  CHECK(first);
  CHECK(significant);
  // τ̂ against its own standard error, where the held-out fit resolves the effect (first, z > 3):
  // (τ̂ − τ)/SE over 4 + 4 shifts −0.00 ± sd 1.07 (bistable), +0.77 ± 0.80 (monostable), over 10
  // + 10 more +0.35 ± 0.92, +0.38 ± 0.94: |z| ≤ 5 is ≥ 4.7 measured sd from the centre (normal:
  // 3e-6 per potential). (A 30 % check of the relative error, +2 % ± sd 15 % and +11 % ± 15 %,
  // failed for ~5 % of seeds: the former KNOWN WEAKNESS.) Below that its SE means little: at the
  // weakest corner, with held-out z 1.4 and 1.6, τ̂ was 14 and 10^13 SE off.
  if (!(r.ranked[0].effect == "colored_noise" && r.ranked[0].held_out_significant)) return;
  const diagnose::Suspect& sp = r.ranked[0];
  tally(pot + " tau", sp.params.at("tau") / tau - 1.0);
  REQUIRE(sp.params_stderr.count("tau"));
  const double tau_z = (sp.params.at("tau") - tau) / sp.params_stderr.at("tau");
  tally(pot + " tau z", tau_z);
  CHECK(std::abs(tau_z) <= 5.0);
}

// The two tests of the suspect at the weakest corner of the drawn range (not run by ctest; ≈ 45
// CPU s a run): scripts/seed-study.sh 14 build/tests/test_diagnose "[coloured_corner]".
TEST_CASE("suspects: a hidden OU excitation at the weakest corner of the drawn range",
          "[.][bench][coloured_corner]") {
  const std::string pot = GENERATE(std::string("bistable"), std::string("monostable"));
  const ColouredCase c = coloured_case(pot, 1.0, 0.02, 6110);
  const auto& r = c.held_out;
  if (!r.ranked.empty()) {
    tally(pot + " held-out first", r.ranked[0].effect == "colored_noise");
    tally(pot + " held-out z", r.ranked[0].z);
    if (r.ranked.size() > 1) tally(pot + " held-out lead", r.ranked[0].evidence - r.ranked[1].evidence);
  }
  if (const auto* sp = find_suspect(r, "colored_noise"); sp && sp->params_stderr.count("tau"))
    tally(pot + " tau z", (sp->params.at("tau") - 1.0) / sp->params_stderr.at("tau"));
  const auto sr = score_tests_of(c.base, c.data, 0.0);
  if (const auto* sp = find_score(sr, "colored_noise")) {
    tally(pot + " score z", sp->z);
    tally(pot + " score z over claim", sp->z - diagnose::normal_isf(sr.threshold));
    tally(pot + " score first", sr.ranked[0].effect == "colored_noise");
    if (sr.ranked.size() > 1 && sr.ranked[0].effect == "colored_noise")
      tally(pot + " score lead", sr.ranked[0].z - sr.ranked[1].z);
    else
      tally(pot + " score lead", sp->z - sr.ranked[0].z);
  }
}

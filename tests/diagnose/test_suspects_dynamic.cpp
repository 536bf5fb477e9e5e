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
void check_first(const diagnose::SuspectReport& r, const std::string& effect, bool held_out_significance = true) {
  INFO(describe(r));
  if (!r.ranked.empty()) {
    tally(effect + " first", r.ranked[0].effect == effect);
    tally(effect + " z", r.ranked[0].z);
    if (r.ranked.size() > 1) tally(effect + " evidence lead", r.ranked[0].evidence - r.ranked[1].evidence);
  }
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
  diagnose::ScoreSuspectOptions so;
  so.max_samples = 1e5;
  const auto sr = diagnose::score_suspects(base, d, 0.0, so);
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

TEST_CASE("suspects: a hidden OU (coloured) excitation is ranked first and significant",
          "[diagnose][suspects][dynamic]") {
  const std::string pot = GENERATE(std::string("bistable"), std::string("monostable"));
  std::mt19937_64 g(seed(pot == "bistable" ? 74 : 75));
  Model truth = hidden_effect_potential(pot);
  Effect e;
  e.id = EffectId::ColoredNoise;
  e.params = {{"tau", uniform(g, 0.2, 1.0)}, {"intensity", uniform(g, 0.02, 0.06)}};
  truth.effects = {e};
  const Dataset d = simulate_hidden(truth, 6000 + g() % 1000, 8, 40000);
  const auto r = suspects_of(baseline_fit(d), d);
  check_first(r, "colored_noise");
  INFO(describe(r));
  tally(pot + " tau", r.ranked[0].params.at("tau") / e.param("tau") - 1.0);
  REQUIRE(r.ranked[0].params_stderr.count("tau"));
  const double tau_z = (r.ranked[0].params.at("tau") - e.param("tau")) / r.ranked[0].params_stderr.at("tau");
  tally(pot + " tau z", tau_z);
  // tau over 3 + 3 seed shifts: relative error +2 % ± sd 15 % (bistable), +11 % ± 15 %
  // (monostable) — a 30 % check failed for ~5 % of seeds (the former KNOWN WEAKNESS). Checked
  // against its own standard error instead: (τ̂ − τ)/SE over 4 + 4 shifts −0.00 ± sd 1.07
  // (bistable), +0.77 ± 0.80 (monostable): |z| ≤ 5 is ≥ 4.7 measured sd from the centre
  // (normal: 3e-6 per potential).
  CHECK(std::abs(tau_z) <= 5.0);
}

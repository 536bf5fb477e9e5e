// Suspects for the dynamic effects (impact stops, harmonic forcing, electromechanical
// coupling, coloured OU excitation): data simulated as a sensor samples a continuous process (fine internal steps) with
// the effect hidden, parameters drawn at random within physical ranges by the test; the baseline
// (the potential's own terms) is fitted by identify; rank_suspects must rank the hidden effect
// first and significant. Control data (no hidden effect) give no significant dynamic suspect.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>

#include "vehs/core/model.hpp"
#include "vehs/diagnose/score_suspects.hpp"
#include "vehs/diagnose/suspects.hpp"
#include "vehs/identify/identify.hpp"
#include "vehs/likelihood/refine.hpp"
#include "vehs/sim/simulate.hpp"

#include "../identify/identify_fixtures.hpp"
#include "diagnose_fixtures.hpp"
#include "score_runs.hpp"

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
          "[diagnose][suspects][dynamic][long]") {
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

ColouredCase coloured_case(const std::string& pot, double tau, double intensity, std::uint64_t data_seed,
                           int records = 8) {
  ColouredCase c;
  c.truth = hidden_effect_potential(pot);
  Effect e;
  e.id = EffectId::ColoredNoise;
  e.params = {{"tau", tau}, {"intensity", intensity}};
  c.truth.effects = {e};
  c.data = simulate_hidden(c.truth, data_seed, records, 40000);
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
  // all the data (computed only then): first there — alone or leading the hidden states' group
  // (score_suspects.hpp: when both hidden states are significant, their refits by the likelihood
  // rank them) — and colored_noise's own score test significant.
  // Over 10 + 10 seed shifts (scripts/seed-study.sh 10 build/tests/test_diagnose "suspects: a
  // hidden OU*") the held-out test was first every time with z 6.1 ± sd 1.6, min 3.8, but it
  // falls short at weak draws. At the weakest corner of the drawn range (intensity 0.02, tau 1.0;
  // tau 0.2 is far stronger; CORNER_POT=monostable CORNER_HELD_OUT=0 scripts/seed-study.sh 20
  // build/tests/test_diagnose "[coloured_corner]", ≈ 33 CPU s a run with the refits):
  //  * bistable (20 shifts before the refits): held out first in 17, the score tests first in
  //    20, colored_noise ahead of the runner-up (electromechanical_coupling) by 4.35 ± sd 1.03 in
  //    z (min 2.6; 4.2 sd: P(< 0) ≈ 1.3e-5, normal fit); with the refits (8 shifts) first and
  //    alone in 8 (2ΔlogL 82–135 where both were significant, 6 of 8).
  //  * monostable: held out first in 11 of 20 (z 3.1 ± 1.0); the score z's alone put colored_noise
  //    ahead of electromechanical_coupling by only 0.95 ± 0.44 (1.6 % the wrong way round, the
  //    former KNOWN WEAKNESS). Both are significant in every shift, so their refits are compared:
  //    colored_noise first in 13 of 13 shifts (alone in 12), 2ΔlogL 7.2, 14.7, 22.6 … 44.2, 214;
  //    plus the shift both old rankings missed (intensity 0.03, shift 7): 19.6. √(2ΔlogL) (≈ normal,
  //    sd 1 asymptotically) 5.35 ± sd 1.15 without the one high value: P(< 0) ≈ 2e-6 (normal fit);
  //    with it, 6.06 ± 2.80 (the sd inflated by the harmless upper tail): 1.5 %. 20 more shifts
  //    (SHIFT0=21 … 40, 24 Nov 16:27 UTC): colored_noise first and alone in 20 of 20, the refits
  //    compared in 16 (electromechanical_coupling not significant in 4), 2ΔlogL 21.1 … 38.1 and
  //    145, 229 — over 33 shifts first in 33, alone in 32, the smallest 2ΔlogL 7.2. √(2ΔlogL)
  //    under 10 (the new 14 and the first run's 3 smallest): 5.05 ± sd 0.87, P(< 0) ≈ 3e-9
  //    (normal fit); and the check fails only when the held-out ranking also falls short (≈ 45 %).
  // colored_noise's z above the claim's (≈ 3.1: α = 0.01 over the tested effects, Bonferroni over
  // the τ grid): bistable 8.5 ± 1.4 (min 5.7), monostable 10.9 ± 1.3 (min 8.3): ≥ 6.2 sd,
  // P(not significant) ≤ 3e-10. Per run: ≤ 1.3e-5 bistable, ≈ 3e-9 monostable (normal fits), at the corner,
  // the worst of the drawn range.
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

// The two tests of the suspect at the weakest corner of the drawn range (not run by ctest; ≈ 25
// CPU s a run and potential, +≈ 30 when the hidden states' refits run):
// scripts/seed-study.sh 20 build/tests/test_diagnose "[coloured_corner]".
// Tallies per potential: each ranking's first and lead (held-out margin and score lead signed:
// colored_noise's over the best other), the score z over the claim's and over every effect but
// electromechanical_coupling, and the hidden states' look-alike comparison: whether it ran, the
// true state first (alone or the group's leader), named alone, the other named alone (a false
// naming), 2ΔlogL signed (the true state's refit over the other's).
// Reverse control (env CORNER_HIDDEN=electromechanical_coupling): a hidden electromechanical
// state (CORNER_COUPLING, 0.3; CORNER_LAMBDA, 1.0) instead of the OU excitation.
TEST_CASE("suspects: a hidden OU excitation at the weakest corner of the drawn range",
          "[.][bench][coloured_corner]") {
  // env CORNER_POT (bistable, monostable; default both), CORNER_INTENSITY (0.02), CORNER_TAU
  // (1.0), CORNER_RECORDS (8), CORNER_HELD_OUT (1; 0 skips the held-out ranking): other corners,
  // record counts and the hidden state for the same study
  auto env = [](const char* k, double d) { return std::getenv(k) ? std::atof(std::getenv(k)) : d; };
  const std::string pot = GENERATE(std::string("bistable"), std::string("monostable"));
  if (std::getenv("CORNER_POT") && pot != std::getenv("CORNER_POT")) return;
  const std::string hidden = std::getenv("CORNER_HIDDEN") ? std::getenv("CORNER_HIDDEN") : "colored_noise";
  const std::string other = hidden == "colored_noise" ? "electromechanical_coupling" : "colored_noise";
  Effect e;
  if (hidden == "colored_noise") {
    e.id = EffectId::ColoredNoise;
    e.params = {{"tau", env("CORNER_TAU", 1.0)}, {"intensity", env("CORNER_INTENSITY", 0.02)}};
  } else {
    e.id = EffectId::ElectromechanicalCoupling;
    e.params = {{"lambda", env("CORNER_LAMBDA", 1.0)}, {"coupling", env("CORNER_COUPLING", 0.3)}};
  }
  Model truth = hidden_effect_potential(pot);
  truth.effects = {e};
  const Dataset data = simulate_hidden(truth, 6110, static_cast<int>(env("CORNER_RECORDS", 8)), 40000);
  const Model base = baseline_fit(data);
  const std::string tag = pot + " " + (hidden == "colored_noise" ? "" : "electro ");
  if (env("CORNER_HELD_OUT", 1) != 0) {
    const auto r = suspects_of(base, data);
    if (!r.ranked.empty()) {
      tally(tag + "held-out first", r.ranked[0].effect == hidden);
      tally(tag + "held-out z", r.ranked[0].z);
      if (r.ranked.size() > 1) tally(tag + "held-out lead", r.ranked[0].evidence - r.ranked[1].evidence);
    }
    if (const auto* sp = find_suspect(r, "colored_noise"); sp && sp->params_stderr.count("tau") && hidden == "colored_noise")
      tally(tag + "tau z", (sp->params.at("tau") - env("CORNER_TAU", 1.0)) / sp->params_stderr.at("tau"));
    if (const auto* cn = find_suspect(r, hidden)) {  // signed: the hidden state's over the best other
      double best_other = -std::numeric_limits<double>::infinity();
      for (const auto& o : r.ranked)
        if (o.effect != hidden) best_other = std::max(best_other, o.evidence);
      tally(tag + "held-out margin", cn->evidence - best_other);
    }
  }
  const auto sr = score_tests_of(base, data, 0.0);
  INFO(score_test::describe(sr));
  const auto* sc = find_score(sr, hidden);
  if (!sc || sr.ranked.empty()) return;
  double best_other = 0.0;  // the hidden state's score z over the best effect but the two hidden states
  for (const auto& o : sr.ranked)
    if (o.effect != hidden && o.effect != other) best_other = std::max(best_other, o.z);
  tally(tag + "score margin over non-look-alikes", sc->z - best_other);
  tally(tag + "score z", sc->z);
  tally(tag + "score z over claim", sc->z - diagnose::normal_isf(sr.threshold));
  if (const auto* so = find_score(sr, other)) tally(tag + "score z lead over the other state", sc->z - so->z);
  // the hidden states' look-alike comparison (score_suspects.hpp)
  const auto& top = sr.ranked[0];
  const auto& la = sc->look_alikes;
  tally(tag + "refits compared", !la.compared.empty());
  if (!la.compared.empty())
    tally(tag + "refit 2dlogL (true over other)", la.compared[0] == hidden ? la.two_delta_log_l : -la.two_delta_log_l);
  // env CORNER_TRUTH_REFIT=1: the true state's refit started from the truth instead, over the
  // group's refit of it (< 0: the group's refit stopped short of the optimum)
  if (std::getenv("CORNER_TRUTH_REFIT") && !la.compared.empty()) {
    likelihood::RefineOptions o;
    o.covariance = likelihood::Covariance::Fisher;
    const double l = likelihood::refine({truth, 0.0, {}}, data, o).log_likelihood;
    const std::size_t i = la.compared[0] == hidden ? 0 : 1;
    tally(tag + "true state refit from the truth over the group's (2dlogL)", 2.0 * (l - la.log_likelihoods[i]));
  }
  tally(tag + "first (alone or leader)", top.effect == hidden);
  tally(tag + "named alone", top.effect == hidden && top.significant && top.not_resolved_from.empty());
  tally(tag + "other named alone", top.effect == other && top.significant && top.not_resolved_from.empty());
  UNSCOPED_INFO(score_test::describe(sr));
}

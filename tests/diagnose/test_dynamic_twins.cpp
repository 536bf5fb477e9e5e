// Lens and twins of models WITH dynamic effects (issue 7): harmonic forcing in the records' absolute
// time (records starting at different t0), impact stops, the electromechanical hidden state and
// coloured excitation. On data simulated from such a model, diagnosing the true model must be
// adequate for at least 7 of 10 seeds (false failure ≤ 1e-4, see there); dropping an effect must
// be detected.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

#include "../../src/diagnose/comparison.hpp"
#include "diagnose_fixtures.hpp"

using namespace diag_test;
using vehs::diagnose::Result;

namespace {

/// Bistable harvester with stops, forcing, an electrical state and coloured excitation. `phase` is
/// the forcing phase at t = 0 of the time axis the records' t column uses.
vehs::Model dynamic_model(double phase, double coupling = 0.08) {
  return model_of(R"({"drift": {"x": 1.0, "x^3": -1.0, "y": -0.1},
                      "diffusion": {"1": 0.015, "x^2": 0.01},
                      "effects": [
                        {"name": "impact_stop", "params": {"k_stop": 6.0, "gap": 1.25}},
                        {"name": "harmonic_forcing", "params": {"amplitude": 0.08, "omega": 1.1, "phase": )" +
                  std::to_string(phase) + R"(}},
                        {"name": "electromechanical_coupling", "params": {"lambda": 0.6, "coupling": )" +
                  std::to_string(coupling) + R"(}},
                        {"name": "colored_noise", "params": {"tau": 0.4, "intensity": 0.006}}]})");
}

/// Records of the model in two groups of `records` each starting at absolute times t0 = 37.3 and
/// 112.9 (a logger that was started and stopped): each group is simulated from its own t = 0 with
/// the forcing phase shifted accordingly, then stamped with its absolute t0.
vehs::Dataset two_epochs(double phase, std::uint64_t seed, double coupling = 0.08, int records = 16) {
  const double omega = 1.1;
  vehs::Dataset out;
  const double t0s[2] = {37.3, 112.9};
  for (int g = 0; g < 2; ++g) {
    DataSpec s;
    s.records = records;
    s.samples = 6000;
    s.dt = 0.02;
    s.substeps = 10;
    s.scheme = vehs::sim::Scheme::Taylor15;
    s.seed = seed * 2 + static_cast<std::uint64_t>(g);
    const auto d = simulate(dynamic_model(phase + omega * t0s[g], coupling), s);
    for (auto r : d.records) {
      const std::size_t off = r.offset;
      r.offset = out.x.size();
      r.t0 = t0s[g];
      r.id = static_cast<long long>(out.records.size());
      out.x.insert(out.x.end(), d.x.begin() + static_cast<std::ptrdiff_t>(off),
                   d.x.begin() + static_cast<std::ptrdiff_t>(off + r.size));
      out.records.push_back(r);
    }
  }
  return out;
}

std::string describe(const Result& r) {
  std::string s = vehs::enum_to_string(vehs::diagnose::kVerdictNames, r.verdict) + " score " +
                  std::to_string(r.score) + ":";
  for (const auto& c : r.components)
    s += " " + c.name + " p=" + (c.test.available ? std::to_string(c.test.p_value) : "n/a");
  return s;
}

/// Records every component's log10(p / threshold) of a diagnosis for seed studies, and the
/// smallest p's normal equivalent Φ⁻¹(1 − p) above the threshold's ("z margin": < 0 adequate).
void tally_components(const std::string& label, const Result& r) {
  double pmin = 1.0;
  for (const auto& c : r.components)
    if (c.test.available) {
      vehs_test::tally(label + " " + c.name + " log10(p/threshold)",
                       std::log10(std::max(1e-300, c.test.p_value) / r.threshold));
      pmin = std::min(pmin, c.test.p_value);
    }
  vehs_test::tally(label + " z margin", vehs::diagnose::normal_isf(std::max(1e-300, pmin)) -
                                            vehs::diagnose::normal_isf(r.threshold));
}

vehs::diagnose::Options options(std::uint64_t seed) {
  auto o = fast_options(seed);
  o.fpk = false;
  o.suspects.enabled = false;
  return o;
}

}  // namespace

TEST_CASE("calibration with dynamic effects: the true model (stops, forcing in absolute time, electrical "
          "state, coloured excitation) is adequate on its own data for at least 7 of 10 seeds",
          "[diagnose][calibration][dynamic]") {
  const double phase = 0.7;
  int adequate = 0;
  const int seeds = 10;
  for (int k = 1; k <= seeds; ++k) {
    const auto d = two_epochs(phase, 8100 + static_cast<std::uint64_t>(k));
    const Result r = vehs::diagnose::diagnose(dynamic_model(phase), d, options(static_cast<std::uint64_t>(k)));
    UNSCOPED_INFO("seed " << k << ": " << describe(r));
    tally_result("true dynamic model", r);
    CHECK(r.lens.kinematics == vehs::diagnose::Kinematics::Central);
    adequate += r.adequate();
  }
  // α = 1 % family-wise; with a calibration error up to 2 × α: P(Bin(10, 0.98) < 7) = 3.1e-5 (the
  // former 9 of 10: 1.6e-2). The adequate fraction over seed shifts: bench/results/.
  CHECK(adequate >= vehs_test::binomial_floor(10, 0.98));
}

TEST_CASE("with dynamic effects, a wrong forcing phase (time origin ignored) and a missing electrical state "
          "are detected", "[diagnose][dynamic]") {
  const double phase = 0.7;
  // the same model with the forcing phase referred to each record's start instead of the absolute
  // time, on 2 × 32 records
  {
    const auto d = two_epochs(phase, 8200, 0.08, 32);
    auto wrong = dynamic_model(phase);
    for (auto& e : wrong.effects)
      if (e.id == vehs::EffectId::HarmonicForcing) e.params["phase"] = phase + 2.0;
    const Result r = vehs::diagnose::diagnose(wrong, d, options(1));
    INFO("wrong phase: " << describe(r));
    tally_result("wrong phase", r);
    tally_components("wrong phase", r);
    // Power over 24 seed shifts (scripts/seed-study.sh 24 build/tests/test_diagnose "*a wrong
    // forcing phase*"; the smallest p is residual_lines'): its normal equivalent Φ⁻¹(1 − p) lies
    // 6.49 ± sd 0.59 (min 5.42) above the verdict threshold's, and "adequate" needs it below: 11
    // sd away (normal: < 1e-20; 8.3 sd even at the upper 95 % limit of the sd, 0.78). On the
    // former 2 × 16 records it was 3.4 ± 1.1 over 10 shifts (≈ 7e-4 per run, the former flake).
    CHECK(!r.adequate());
  }
  {
    // the electrical state with coupling 0.2 (0.08 above): at 0.08 these 32 × 6000 samples
    // resolve it at the edge (the verdict's log10(min p / threshold) −1.2, −0.04, −2.0, −0.14
    // over 4 seed shifts without the score tests; −0.9 ± 1.1 with them, the score test's z
    // 3.3 ± 1.0: false failure 10–30 % per seed, the former KNOWN WEAKNESS). At 0.2 with the
    // score tests on all the data, over 24 seed shifts: the smallest p's normal equivalent 6.41
    // ± sd 1.36 (min 3.25) above the threshold's, 4.7 sd (normal: 1.2e-6 per run; 3.5 sd, 2e-4,
    // at the upper 95 % limit of the sd, 1.81); the score test names electromechanical_coupling
    // first in 24 of 24 with z 9.6 ± 1.4. (On 10^5 of the samples, as before: 3.4 ± 1.0 over 8
    // shifts, ≈ 4e-4 per run.)
    const double coupling = 0.2;
    const auto d2 = two_epochs(phase, 8300, coupling);
    auto without = dynamic_model(phase, coupling);
    without.effects.erase(std::remove_if(without.effects.begin(), without.effects.end(),
                                         [](const vehs::Effect& e) { return e.id == vehs::EffectId::ElectromechanicalCoupling; }),
                          without.effects.end());
    auto o = options(2);
    o.score_suspects.enabled = true;  // the likelihood's score tests on all the data (issue 13)
    o.score_suspects.max_samples = 0;  // all 192000 samples (see above)
    o.score_suspects.grid = 3;
    const Result r = vehs::diagnose::diagnose(without, d2, o);
    INFO("without the electrical state: " << describe(r));
    tally_result("without electrical state", r);
    tally_components("without electrical state", r);
    if (!r.score_suspects.ranked.empty()) {
      vehs_test::tally("score first electro", r.score_suspects.ranked[0].effect == "electromechanical_coupling");
      vehs_test::tally("score z", r.score_suspects.ranked[0].z);
    }
    CHECK(!r.adequate());
  }
}

// Exploration aid (not run by ctest): VEHS_DT_KEEP = comma-separated effect names to keep,
// VEHS_DT_T0 = 1 to stamp absolute t0s.
TEST_CASE("dynamic twins explore", "[.][bench][explore_dt]") {
  const char* keep = std::getenv("VEHS_DT_KEEP");
  if (!keep) return;
  const std::string k = keep;
  const bool t0 = std::getenv("VEHS_DT_T0") && std::string(std::getenv("VEHS_DT_T0")) == "1";
  auto filt = [&](vehs::Model m) {
    m.effects.erase(std::remove_if(m.effects.begin(), m.effects.end(),
                                   [&](const vehs::Effect& e) { return k.find(e.name()) == std::string::npos; }),
                    m.effects.end());
    return m;
  };
  DataSpec s;
  s.records = 32;
  s.samples = 6000;
  s.dt = 0.02;
  s.substeps = 10;
  s.scheme = vehs::sim::Scheme::Taylor15;
  s.seed = 99;
  const double phase = 0.7;
  vehs::Dataset d;
  if (t0) {
    d = two_epochs(phase, 99);  // all effects: only meaningful with the full model
  } else {
    d = simulate(filt(dynamic_model(phase)), s);
  }
  const Result r = vehs::diagnose::diagnose(filt(dynamic_model(phase)), d, options(1));
  WARN(k << ": " << describe(r) << " twins " << vehs::enum_to_string(vehs::sim::kSchemeNames, r.sampling.twin_scheme) << " x" << r.sampling.twin_substeps << " data " << vehs::enum_to_string(vehs::kSamplingVerdictNames, r.sampling.data_verdict) << " lens " << r.lens.describe());
}

// The sampling diagnosis of a model with a coloured excitation takes the excitation's known
// memory out of the model's residuals (src/diagnose/sampling.cpp): without it, τ = 12 samples
// read as 7–12 % sensor noise on noise-free data and the true model was inadequate on its own
// data in 7 of 10 seeds of issue 13's loop study. Exact check of that memory: for an
// exponential covariance V e^{−|s|/τ} seen through the triangle weight (h − |s|)/h² on [−h, h],
// lags l ≥ 2 do not overlap, so the filtered covariance factorises into
// V e^{−l·h/τ} · [(2τ²/h²)(cosh(h/τ) − 1)]² (deterministic: midpoint rule within 1e-3).
TEST_CASE("dynamic twins: the coloured excitation's memory through the lens, against its closed form", "[diagnose]") {
  for (const double tau_over_h : {12.0, 0.5}) {
    const double h = 0.05, tau = tau_over_h * h, intensity = 0.04;
    const vehs::Model m = model_of(R"({"drift": {"x": 1.0, "x^3": -1.0, "y": -0.1}, "diffusion": {"1": 0.01},
        "effects": [{"name": "colored_noise", "params": {"tau": )" + std::to_string(tau) +
                                   R"(, "intensity": 0.04}}]})");
    const auto c = vehs::diagnose::detail::colored_autocovariance(m, h);
    const double v = intensity / (2.0 * tau), g = 2.0 * tau * tau / (h * h) * (std::cosh(h / tau) - 1.0);
    for (int l = 2; l < 4; ++l) CHECK(c[std::size_t(l)] == Approx(v * std::exp(-l * h / tau) * g * g).epsilon(1e-3));
    CHECK(c[0] < v);  // the lens averages: less than the excitation's variance
    CHECK(c[0] > c[1]);
  }
  const auto none = vehs::diagnose::detail::colored_autocovariance(bistable(), 0.05);
  CHECK(none[0] == 0.0);
}

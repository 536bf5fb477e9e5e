// Dynamic effects (impact stops, harmonic forcing, electromechanical coupling) identified from
// continuous-time records (fine internal steps) of two potentials, with parameters drawn at
// random within physical ranges by the test; identify never sees them. Checks: every effect
// parameter and baseline term within z_limit(k) standard errors for the test case's k z-checks
// (identify_fixtures.hpp: false failure ≤ 1e-4), every effect parameter resolved (SE ≤ 15 % of
// the truth), the distractor terms dropped or insignificant (check_support), and the written
// model simulates. Biases over seeds: scripts/seed-study.sh 50 build/tests/test_identify
// "[dynamic]" and tests/identify/test_bias_study.cpp.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "identify_fixtures.hpp"
#include "vehs/core/error.hpp"
#include "vehs/identify/dynamic.hpp"
#include "vehs/io/model_file.hpp"

using namespace vehs;
using namespace vehs_test;

namespace {

identify::Options options_for(const Model& base) {
  identify::Options o;
  // x^2 as a distractor the selection must drop (x^5 is left out: over the small range of a
  // stopped monostable oscillator x^3 and x^5 are nearly collinear)
  o.drift_library = {Term::parse("x"), Term::parse("x^2"), Term::parse("x^3"), Term::parse("y")};
  o.diffusion_library = paper_diffusion_library(2);
  if (std::getenv("NOSSR")) {
    o.drift_library = {Term::parse("x"), Term::parse("x^3"), Term::parse("y")};
    o.sparsity = identify::Sparsity::None;
  }
  (void)base;
  return o;
}

/// The baseline terms (x, x³, y; 1, x²) as k of the test case's z-checks.
void check_baseline(const Model& learned, const Model& truth, int k) {
  const Deviation d = compare(learned, truth);
  CHECK(d.max_z <= z_limit(k));
}

}  // namespace

TEST_CASE("dynamic effects: harmonic forcing (frequency, amplitude, phase) on two potentials",
          "[identify][dynamic][harmonic]") {
  const std::string pot = GENERATE(std::string("bistable"), std::string("monostable"));
  std::mt19937_64 g(seed(pot == "bistable" ? 11 : 12));
  Model truth = hidden_effect_potential(pot);
  Effect e;
  e.id = EffectId::HarmonicForcing;
  e.params = {{"amplitude", uniform(g, 0.05, 0.12)}, {"omega", uniform(g, 0.6, 2.0)}, {"phase", uniform(g, -3.0, 3.0)}};
  truth.effects = {e};
  const Dataset d = simulate_hidden(truth, 100 + g() % 1000);
  identify::Options o = options_for(truth);
  Effect req;
  req.id = EffectId::HarmonicForcing;
  o.effects = {req};
  const identify::Result r = identify::identify(d, o);
  check_written_covariance(r.model);  // the sandwich over drift and effect parameters (issue 15)
  INFO(pot << ": " << model_to_json(r.model)["dynamic_fit"].dump() << " drift " << model_to_json(r.model)["drift"].dump() << " estimator " << model_to_json(r.model)["estimator"]["used"].dump());
  REQUIRE(r.model.effects.size() == 1);
  const Effect& f = r.model.effects[0];
  // 8 z-checks: omega, amplitude, phase and the 5 baseline terms
  check_effect_param(f, "omega", e.param("omega"), 8);
  check_effect_param(f, "amplitude", e.param("amplitude"), 8);
  // phase: compare on the circle
  {
    const double dphi = std::remainder(f.param("phase") - e.param("phase"), 2.0 * M_PI);
    const double se = f.stderr_.at("phase");
    INFO("phase: true " << e.param("phase") << ", fitted " << f.param("phase") << " +- " << se);
    tally("harmonic_forcing.phase", dphi / se);
    CHECK(std::abs(dphi) <= z_limit(8) * se);
    CHECK(se <= 0.15 * M_PI);
  }
  truth.effects.clear();
  check_baseline(r.model, truth, 8);
  check_support(r.model, truth, 2);  // the distractors x^2 (drift) and x (diffusion)
  // the model file round-trips and validates
  const Model back = model_from_json(nlohmann::json(model_to_json(r.model)), "written");
  validate_model(back, "written");
  REQUIRE(back.effects.size() == 1);
}

TEST_CASE("dynamic effects: impact stops (stiffness and both gaps) on two potentials",
          "[identify][dynamic][impact]") {
  const std::string pot = GENERATE(std::string("bistable"), std::string("monostable"));
  std::mt19937_64 g(seed(pot == "bistable" ? 21 : 22));
  Model truth = hidden_effect_potential(pot);
  const Effect e = draw_impact_stop(truth, g);  // gaps at a random quantile of |x| without stops
  truth.effects = {e};
  const Dataset d = simulate_hidden(truth, 200 + g() % 1000);
  identify::Options o = options_for(truth);
  Effect req;
  req.id = EffectId::ImpactStop;
  o.effects = {req};
  const identify::Result r = identify::identify(d, o);
  check_written_covariance(r.model);  // the sandwich over drift and effect parameters (issue 15)
  INFO(pot << ": " << model_to_json(r.model)["dynamic_fit"].dump() << " drift " << model_to_json(r.model)["drift"].dump() << " estimator " << model_to_json(r.model)["estimator"]["used"].dump());
  REQUIRE(r.model.effects.size() == 1);
  const Effect& f = r.model.effects[0];
  // 8 z-checks: the three stop parameters and the 5 baseline terms. Issue 11: the portable build
  // once gave diffusion "1" z = −3.16 and x^2 z = +3.15 here (the former limit 3); over 200 seeds
  // (bistable, test_bias_study.cpp) the mean z is −0.07 ± 0.07 and +0.10 ± 0.07, sd 1.00 and 0.97,
  // against +0.03 and −0.01 without stops: the stops bias neither diffusion term, and a |z| of
  // 3.2 in one of 8 terms is a 1 % event.
  check_effect_param(f, "k_stop", e.param("k_stop"), 8);
  check_effect_param(f, "gap", e.param("gap"), 8);
  check_effect_param(f, "gap_neg", e.param("gap_neg"), 8);
  truth.effects.clear();
  check_baseline(r.model, truth, 8);
}

// Monostable only: on the bistable potential the spread of the estimates over seeds is about
// 1.5x the sandwich standard error at 64 records (lambda z = +2.1, -1.7, -0.6 and coupling z =
// +2.0, -0.8, +0.1 over three seeds), and one draw stays 3.3 SE off at 160 records — the
// standard errors of this weakly identified effect under-cover there (well hopping; see
// docs/studies/dynamic-effects.md).
TEST_CASE("dynamic effects: electromechanical coupling (time constant and coupling) from x alone",
          "[identify][dynamic][electro]") {
  const std::string pot = "monostable";
  std::mt19937_64 g(seed(32));
  Model truth = hidden_effect_potential(pot);
  Effect e;
  e.id = EffectId::ElectromechanicalCoupling;
  e.params = {{"lambda", uniform(g, 0.6, 1.4)}, {"coupling", uniform(g, 0.3, 0.6)}};
  truth.effects = {e};
  // the hidden state is weakly identifiable against damping and stiffness (its force at one
  // frequency is a mix of both) and its profile estimate has a finite-sample bias of about −1 SE
  // at 32 records (−0.3 SE at 160, measured): 8x the records of the other effects
  const Dataset d = simulate_hidden(truth, 300 + g() % 1000, std::getenv("NREC") ? std::atoi(std::getenv("NREC")) : 64, 40000);
  identify::Options o = options_for(truth);
  Effect req;
  req.id = EffectId::ElectromechanicalCoupling;
  o.effects = {req};
  const identify::Result r = identify::identify(d, o);
  check_written_covariance(r.model);  // the sandwich over drift and effect parameters (issue 15)
  INFO(pot << ": " << model_to_json(r.model)["dynamic_fit"].dump() << " drift " << model_to_json(r.model)["drift"].dump() << " estimator " << model_to_json(r.model)["estimator"]["used"].dump());
  REQUIRE(r.model.effects.size() == 1);
  const Effect& f = r.model.effects[0];
  // 7 z-checks: lambda, coupling and the 5 baseline terms
  // resolution: SE/truth over 9 seed shifts 0.03–0.11 (lambda), 0.07–0.15 (coupling): 30 %
  check_effect_param(f, "lambda", e.param("lambda"), 7, 0.3);
  check_effect_param(f, "coupling", e.param("coupling"), 7, 0.3);
  truth.effects.clear();
  check_baseline(r.model, truth, 7);
}

TEST_CASE("dynamic effects: stops and forcing together, with spurious library terms the selection must drop",
          "[identify][dynamic][joint]") {
  // a selection made without the effects absorbs the stops into x^5 (x^3 changes sign); the
  // first profile fit must run on the full library and the final selection drop x^2 and x^5
  std::mt19937_64 g(seed(41));
  Model truth = hidden_effect_potential("bistable");
  Effect stop, force;
  stop.id = EffectId::ImpactStop;
  stop.params = {{"k_stop", uniform(g, 30.0, 60.0)}, {"gap", uniform(g, 1.25, 1.35)}, {"gap_neg", uniform(g, 1.2, 1.3)}};
  force.id = EffectId::HarmonicForcing;
  force.params = {{"amplitude", uniform(g, 0.08, 0.12)}, {"omega", uniform(g, 0.8, 1.6)}, {"phase", uniform(g, -3.0, 3.0)}};
  truth.effects = {stop, force};
  const Dataset d = simulate_hidden(truth, 400 + g() % 1000, 6, 40000);
  identify::Options o;
  o.drift_library = {Term::parse("x"), Term::parse("x^2"), Term::parse("x^3"), Term::parse("x^5"), Term::parse("y")};
  o.diffusion_library = paper_diffusion_library(2);
  Effect a, b;
  a.id = EffectId::ImpactStop;
  b.id = EffectId::HarmonicForcing;
  o.effects = {a, b};
  const identify::Result r = identify::identify(d, o);
  check_written_covariance(r.model);  // two effects: the columns of both in one sandwich
  INFO(model_to_json(r.model)["dynamic_fit"].dump());
  REQUIRE(r.model.effects.size() == 2);
  const Effect* fs = r.model.find_effect(EffectId::ImpactStop);
  const Effect* ff = r.model.find_effect(EffectId::HarmonicForcing);
  REQUIRE(fs);
  REQUIRE(ff);
  // 10 z-checks: five effect parameters and the 5 baseline terms
  for (const char* k : {"k_stop", "gap", "gap_neg"}) check_effect_param(*fs, k, stop.param(k), 10);
  for (const char* k : {"amplitude", "omega"}) check_effect_param(*ff, k, force.param(k), 10);
  truth.effects.clear();
  check_support(r.model, truth, 3);  // the distractors x^2, x^5 (drift) and x (diffusion)
  check_baseline(r.model, truth, 10);
}

TEST_CASE("dynamic effects: given params are held fixed - unsupported and bad requests fail clearly",
          "[identify][dynamic]") {
  Model truth = hidden_effect_potential("bistable");
  Effect e;
  e.id = EffectId::HarmonicForcing;
  e.params = {{"amplitude", 0.1}, {"omega", 1.3}, {"phase", 0.4}};
  truth.effects = {e};
  const Dataset d = simulate_hidden(truth, 77, 4, 20000);
  identify::Options o = options_for(truth);
  Effect req;
  req.id = EffectId::HarmonicForcing;
  req.params = {{"omega", 1.3}};
  o.effects = {req};
  const identify::Result r = identify::identify(d, o);
  REQUIRE(r.model.effects.size() == 1);
  CHECK(r.model.effects[0].param("omega") == 1.3);
  CHECK(r.model.effects[0].stderr_.count("omega") == 0);
  {
    const double amp = r.model.effects[0].param("amplitude"), se = r.model.effects[0].stderr_.at("amplitude");
    tally("held omega: amplitude", (amp - 0.1) / se, amp / 0.1 - 1);
    tally("held omega: amplitude SE", se);
    // SE ≈ 0.0085. The spread of z looked like 1.5 over 9 seed shifts; over 1500
    // (JOBS=1 scripts/seed-study.sh 1500 build/tests/test_identify "dynamic effects: given params
    // are held fixed*", ≈ 0.1 CPU s a run) z = (amp − 0.1)/SE has mean +0.10 ± 0.03 and sd 1.039
    // ± 0.019, max |z| 3.95: the SE is calibrated to 4 % (the 9-shift 1.5 was chance; a third of
    // the mean is the amplitude's own bias from |(A, B)| = hypot, SE²/(2·amp) = 0.04 SE). As
    // stat_bounds.hpp scales sandwich SEs by the measured spread: z_bound(1) × 1.1 = 4.28, i.e.
    // N(0.10, 1.039) exceeds it with 4e-5 per run (8e-5 at the spread's and the mean's upper 2 se).
    CHECK(std::abs(amp - 0.1) <= 1.1 * z_bound(1) * se);
  }

  Effect bad;
  bad.id = EffectId::HarmonicForcing;
  bad.params = {{"amplitude", 0.1}};
  o.effects = {bad};
  CHECK_THROWS_WITH(identify::identify(d, o), Catch::Contains("amplitude can only be held fixed together with phase"));
  Effect cn;
  cn.id = EffectId::ColoredNoise;
  Effect hf;
  hf.id = EffectId::HarmonicForcing;
  o.effects = {cn, hf};
  CHECK_THROWS_WITH(identify::identify(d, o), Catch::Contains("cannot yet be combined"));
}

TEST_CASE("calibration study: electromechanical coupling over seeds (env NREC, NSEEDS, LAM, CPL, SSR, NOBURN)", "[.calibration]") {
  const int nrec = std::getenv("NREC") ? std::atoi(std::getenv("NREC")) : 32;
  const int nseeds = std::getenv("NSEEDS") ? std::atoi(std::getenv("NSEEDS")) : 6;
  for (int seed = 1; seed <= nseeds; ++seed) {
    std::string pot = "bistable";
    Model truth = pot == "paper" ? paper_truth() : hidden_effect_potential(pot);
    Effect e;
    e.id = EffectId::ElectromechanicalCoupling;
    e.params = {{"lambda", std::getenv("LAM") ? std::atof(std::getenv("LAM")) : 1.0}, {"coupling", std::getenv("CPL") ? std::atof(std::getenv("CPL")) : 0.4}};
    truth.effects = {e};
    const Dataset d = simulate_hidden(truth, 6000 + seed, nrec, 40000, std::getenv("NOBURN") ? 0.0 : 20.0);
    identify::Options io;
    io.drift_library = {Term::parse("x"), Term::parse("x^3"), Term::parse("y")};
    if (pot == "paper") io.drift_library = paper_drift_library(9, 1);
    io.diffusion_library = paper_diffusion_library(2);
    if (std::getenv("SSR")) io.drift_library = {Term::parse("x"), Term::parse("x^2"), Term::parse("x^3"), Term::parse("y")};
    else io.sparsity = identify::Sparsity::None;
    Effect req;
    req.id = EffectId::ElectromechanicalCoupling;
    io.effects = {req};
    const identify::Result r = identify::identify(d, io);
    const Effect& f = r.model.effects[0];
    WARN(pot << " lambda " << f.param("lambda") << " +- " << f.stderr_.at("lambda") << " coupling " << f.param("coupling") << " +- " << f.stderr_.at("coupling")
         << " beta " << r.model.drift_coef("y") << " +- " << r.model.drift_stderr.at("y") << " " << vehs::enum_to_string(vehs::kEstimatorNames, r.model.fit->estimator) << " " << r.report.profile->rounds.size());
  }
}

TEST_CASE("calibration study: impact stops on the monostable potential over 8 seeds", "[.calibration]") {
  Model truth = hidden_effect_potential("monostable");
  Effect e;
  e.id = EffectId::ImpactStop;
  e.params = {{"k_stop", 48.0}, {"gap", 0.554}, {"gap_neg", 0.586}};
  truth.effects = {e};
  for (int seed = 1; seed <= 8; ++seed) {
    const Dataset d = simulate_hidden(truth, 7000 + seed, 8, 40000);
    identify::Options io = options_for(truth);
    Effect req;
    req.id = EffectId::ImpactStop;
    io.effects = {req};
    const identify::Result r = identify::identify(d, io);
    const Effect& f = r.model.effects[0];
    WARN("seed " << seed << " zk " << (f.param("k_stop") - 48.0) / f.stderr_.at("k_stop") << " zg "
                 << (f.param("gap") - 0.554) / f.stderr_.at("gap") << " zgn " << (f.param("gap_neg") - 0.586) / f.stderr_.at("gap_neg")
                 << " zb " << (r.model.drift_coef("y") + 0.1) / r.model.drift_stderr.at("y") << " terms " << model_to_json(r.model)["drift"].dump());
  }
}

TEST_CASE("calibration study: harmonic forcing on the bistable potential over 8 seeds", "[.calibration]") {
  Model truth = hidden_effect_potential("bistable");
  Effect e;
  e.id = EffectId::HarmonicForcing;
  e.params = {{"amplitude", 0.08}, {"omega", 1.2}, {"phase", 0.7}};
  truth.effects = {e};
  for (int seed = 1; seed <= 8; ++seed) {
    const Dataset d = simulate_hidden(truth, 8000 + seed, 8, 40000);
    identify::Options io = options_for(truth);
    Effect req;
    req.id = EffectId::HarmonicForcing;
    io.effects = {req};
    const identify::Result r = identify::identify(d, io);
    const Effect& f = r.model.effects[0];
    WARN("seed " << seed << " zA " << (f.param("amplitude") - 0.08) / f.stderr_.at("amplitude") << " zw "
                 << (f.param("omega") - 1.2) / f.stderr_.at("omega") << " zphi "
                 << std::remainder(f.param("phase") - 0.7, 2 * M_PI) / f.stderr_.at("phase") << " zb "
                 << (r.model.drift_coef("y") + 0.1) / r.model.drift_stderr.at("y"));
  }
}

// Issue 7, the whole loop for the term-like effects: data with a hidden effect (random parameters
// within physical ranges, two potentials, a sensor sampling a continuous process: 10 substeps per
// sample), a baseline of the paper's model form fitted by identify (the code under test never sees
// the truth), then
//   diagnose(baseline)        -> inadequate, the hidden effect ranked first;
//   identify(+ that effect)   -> its parameters within z_limit(k) standard errors, resolved to 15 %;
//   diagnose(refit)           -> adequate at α = 5e-5, the score at most half the baseline's.
// False failures: see missing_physics_loop.hpp (null checks at small α, z-checks at 1e-4, power
// checks with the margins measured over seed shifts).
// And the control: no hidden effect -> adequate and no significant suspect.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <map>
#include <random>
#include <string>

#include "missing_physics_loop.hpp"
#include "vehs/io/model_file.hpp"

using namespace diag_test;
using namespace diag_test::loop;

// Parameter ranges: forces comparable to the linear damping force β·σ_v at the harvester's
// typical velocity σ_v (drag- or friction-dominated harvesters included); the velocity-dependent
// effects are tested under strong excitation (2D = 0.3, σ_v ≈ 1), where they matter.
TEST_CASE("missing physics loop: coulomb_friction hidden in a monostable harvester", "[diagnose][missing_physics]") {
  std::mt19937_64 g(vehs_test::seed(71));
  run_loop({effect("coulomb_friction", {{"mu", uniform(g, 0.06, 0.12)}}), monostable()}, 7101);
}

TEST_CASE("missing physics loop: quadratic_damping hidden in a strongly excited bistable harvester",
          "[diagnose][missing_physics]") {
  std::mt19937_64 g(vehs_test::seed(72));
  run_loop({effect("quadratic_damping", {{"c", uniform(g, 0.35, 0.6)}}), excited(bistable(), 0.3)}, 7201);
}

TEST_CASE("missing physics loop: nonlinear_damping hidden in a strongly excited monostable harvester",
          "[diagnose][missing_physics]") {
  std::mt19937_64 g(vehs_test::seed(73));
  run_loop({effect("nonlinear_damping", {{"c_x2y", uniform(g, 0.3, 0.5)}, {"c_y3", uniform(g, 0.25, 0.4)}}),
            excited(monostable(), 0.3)},
           7301);
}

// asymmetric_stiffness adds five even powers (k0 … k8): their collinearity makes k2's standard
// error about 0.045 here, so 15 % needs k2 >= ~0.5 (a strongly asymmetric double well).
TEST_CASE("missing physics loop: asymmetric_stiffness hidden in a strongly excited bistable harvester",
          "[diagnose][missing_physics]") {
  std::mt19937_64 g(vehs_test::seed(74));
  run_loop({effect("asymmetric_stiffness",
                   {{"k0", 0.0}, {"k2", uniform(g, 0.5, 0.8)}, {"k4", 0.0}, {"k6", 0.0}, {"k8", 0.0}}),
            excited(bistable(), 0.3)},
           7401);
}

TEST_CASE("missing physics loop: velocity_dependent_noise hidden in a strongly excited monostable harvester",
          "[diagnose][missing_physics]") {
  std::mt19937_64 g(vehs_test::seed(75));
  run_loop({effect("velocity_dependent_noise", {{"q_y2", uniform(g, 0.04, 0.08)}}), excited(monostable(), 0.3)},
           7501);
}

TEST_CASE("missing physics control: nothing hidden, adequate and no significant suspect",
          "[diagnose][missing_physics]") {
  for (const auto& [base, seed] : {std::pair{monostable(), 7601ull}, std::pair{excited(bistable(), 0.3), 7602ull}}) {
    const auto d = simulate(base, continuous_spec(seed));
    const vehs::Model baseline = fit(d, kBaselineDrift, kBaselineDiffusion);
    // null checks: each verdict at α = 2.5e-5 family-wise (false failure 5e-5 for the two if the
    // p-values are valid); a significant suspect needs an inadequate verdict besides
    auto o = options(seed);
    o.alpha = 2.5e-5;
    const Result r = vehs::diagnose::diagnose(baseline, d, o);
    INFO(describe(r));
    tally_result("control", r);
    CHECK(r.adequate());
    for (const auto& sp : r.suspects.ranked) CHECK_FALSE(sp.significant);
  }
}

// Exploration aid (not run by ctest): VEHS_MP_EFFECT='{"name": ..., "params": {...}}',
// VEHS_MP_BASE=bistable|monostable, VEHS_MP_SEED, VEHS_MP_SAMPLES, VEHS_MP_DIFFUSION (2D).
TEST_CASE("missing physics explore", "[.][bench][explore_mp]") {
  const char* e = std::getenv("VEHS_MP_EFFECT");
  if (!e) return;
  const std::string base = std::getenv("VEHS_MP_BASE") ? std::getenv("VEHS_MP_BASE") : "bistable";
  vehs::Model m = base == "bistable" ? bistable() : monostable();
  if (const char* D = std::getenv("VEHS_MP_DIFFUSION"))
    for (auto& tc : m.diffusion)
      if (tc.term.name() == "1") tc.coef = std::atof(D);
  const std::uint64_t seed = std::getenv("VEHS_MP_SEED") ? std::strtoull(std::getenv("VEHS_MP_SEED"), nullptr, 10) : 1;
  const vehs::Effect eff = vehs::effect_from_json(nlohmann::json::parse(e), "VEHS_MP_EFFECT", true);
  run_loop({eff, m}, seed);
}

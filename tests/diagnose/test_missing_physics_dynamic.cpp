// Issue 7, the missing-physics loop for the dynamic effects identify can fit (impact_stop,
// harmonic_forcing, electromechanical_coupling): same checks as for the term-like effects
// (test_missing_physics.cpp), with the fitted parameters read from the refit's effects.
// Tagged [bench]: each run takes about 2 minutes on 2 cores (the parameter draws and suspects
// refit the dynamic effects by profile least squares); run by hand:
//   build/tests/test_diagnose "[missing_physics_dynamic]"
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "missing_physics_loop.hpp"

using namespace diag_test;
using namespace diag_test::loop;

TEST_CASE("missing physics loop: impact_stop hidden in a bistable harvester", "[.][bench][missing_physics_dynamic]") {
  std::mt19937_64 g(81);
  const double gap = uniform(g, 1.1, 1.3), k = uniform(g, 3.0, 6.0);
  run_loop({effect("impact_stop", {{"k_stop", k}, {"gap", gap}}), bistable()}, 8101);
}

TEST_CASE("missing physics loop: harmonic_forcing hidden in a bistable harvester", "[.][bench][missing_physics_dynamic]") {
  std::mt19937_64 g(82);
  const double a = uniform(g, 0.05, 0.1), w = uniform(g, 0.8, 1.4), ph = uniform(g, 0.5, 2.5);
  run_loop({effect("harmonic_forcing", {{"amplitude", a}, {"omega", w}, {"phase", ph}}), bistable()}, 8201);
}

TEST_CASE("missing physics loop: electromechanical_coupling hidden in a monostable harvester",
          "[.][bench][missing_physics_dynamic]") {
  std::mt19937_64 g(83);
  // weakly identifiable against damping and stiffness: a strong coupling (as in test_suspects_dynamic)
  const double lambda = uniform(g, 0.6, 1.4), c = uniform(g, 0.3, 0.6);
  run_loop({effect("electromechanical_coupling", {{"lambda", lambda}, {"coupling", c}}), monostable()}, 8301);
}

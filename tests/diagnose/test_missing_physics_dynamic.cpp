// Issue 7, the missing-physics loop for the dynamic effects (impact_stop, harmonic_forcing,
// electromechanical_coupling, colored_noise): same checks as for the term-like effects
// (test_missing_physics.cpp), with the fitted parameters read from the refit's effects.
// The electromechanical loop also exercises diagnose's confirmation of close contenders: on its
// data colored_noise scores about as well on held-out rows and the refits decide.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "missing_physics_loop.hpp"

using namespace diag_test;
using namespace diag_test::loop;

TEST_CASE("missing physics loop: impact_stop hidden in a bistable harvester", "[diagnose][missing_physics]") {
  std::mt19937_64 g(81);
  const double gap = uniform(g, 1.1, 1.3), k = uniform(g, 3.0, 6.0);
  run_loop({effect("impact_stop", {{"k_stop", k}, {"gap", gap}}), bistable()}, 8101, 6000, 32);
}

TEST_CASE("missing physics loop: harmonic_forcing hidden in a bistable harvester", "[diagnose][missing_physics]") {
  std::mt19937_64 g(82);
  const double a = uniform(g, 0.05, 0.1), w = uniform(g, 0.8, 1.4), ph = uniform(g, 0.5, 2.5);
  run_loop({effect("harmonic_forcing", {{"amplitude", a}, {"omega", w}, {"phase", ph}}), bistable()}, 8201, 6000, 32);
}

TEST_CASE("missing physics loop: electromechanical_coupling hidden in a monostable harvester",
          "[diagnose][missing_physics]") {
  std::mt19937_64 g(83);
  // Weakly identifiable against damping and stiffness: most of its force looks like extra
  // damping and stiffness, only the frequency dependence tells it apart. Measured over 6 draws
  // (λ in [0.6, 1.4], two potentials, 64 records): coupling in [0.3, 0.6] with 6000 samples per
  // record left the baseline adequate or the suspect below z = 3 in 4 of 6; coupling in
  // [0.6, 1.0] with 10000 samples passed the whole loop in 5 of 6 (the sixth, bistable: λ 2.6 SE
  // and 15.6 % low).
  const double lambda = uniform(g, 0.6, 1.4), c = uniform(g, 0.6, 1.0);
  run_loop({effect("electromechanical_coupling", {{"lambda", lambda}, {"coupling", c}}), monostable()}, 8301, 10000);
}

// An OU excitation instead of white noise (tau from 10 to 50 samples): diagnose must name
// colored_noise, not a deterministic slow force, and the refit must leave an adequate model.
TEST_CASE("missing physics loop: colored_noise hidden in a bistable harvester", "[diagnose][missing_physics]") {
  std::mt19937_64 g(84);
  const double tau = uniform(g, 0.2, 1.0), intensity = uniform(g, 0.02, 0.06);
  run_loop({effect("colored_noise", {{"tau", tau}, {"intensity", intensity}}), bistable()}, 8401);
}

// Issue 7, the missing-physics loop for the dynamic effects (impact_stop, harmonic_forcing,
// electromechanical_coupling, colored_noise): same checks as for the term-like effects
// (test_missing_physics.cpp), with the fitted parameters read from the refit's effects.
// The electromechanical loop also exercises diagnose's confirmation of close contenders: on its
// data colored_noise scores about as well on held-out rows and the refits decide.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "missing_physics_loop.hpp"
#include "vehs/io/model_file.hpp"

using namespace diag_test;
using namespace diag_test::loop;

TEST_CASE("missing physics loop: impact_stop hidden in a bistable harvester", "[diagnose][missing_physics]") {
  std::mt19937_64 g(vehs_test::seed(81));
  const double gap = uniform(g, 1.1, 1.3), k = uniform(g, 3.0, 6.0);
  run_loop({effect("impact_stop", {{"k_stop", k}, {"gap", gap}}), bistable()}, 8101, 6000, 32);
}

TEST_CASE("missing physics loop: harmonic_forcing hidden in a bistable harvester", "[diagnose][missing_physics]") {
  std::mt19937_64 g(vehs_test::seed(82));
  const double a = uniform(g, 0.05, 0.1), w = uniform(g, 0.8, 1.4), ph = uniform(g, 0.5, 2.5);
  run_loop({effect("harmonic_forcing", {{"amplitude", a}, {"omega", w}, {"phase", ph}}), bistable()}, 8201, 6000, 32);
}

TEST_CASE("missing physics loop: electromechanical_coupling hidden in a monostable harvester",
          "[diagnose][missing_physics][long]") {
  std::mt19937_64 g(vehs_test::seed(83));
  // Weakly identifiable against damping and stiffness: most of its force looks like extra
  // damping and stiffness, only the frequency dependence tells it apart. Over random draws
  // ("[explore_draws]" below): coupling in [0.6, 1.0] with 10000 samples per record, the whole
  // loop held in 5 of 6 (draw 3, bistable: λ 17.6 % low at 3.2 SE); coupling in [0.3, 0.6] with
  // 6000 samples it failed in 3 of the first 4.
  const double lambda = uniform(g, 0.6, 1.4), c = uniform(g, 0.6, 1.0);
  run_loop({effect("electromechanical_coupling", {{"lambda", lambda}, {"coupling", c}}), monostable()}, 8301, 10000);
}

// An OU excitation instead of white noise (tau from 10 to 50 samples): diagnose must name
// colored_noise, not a deterministic slow force, and the refit must leave an adequate model.
TEST_CASE("missing physics loop: colored_noise hidden in a bistable harvester", "[diagnose][missing_physics]") {
  std::mt19937_64 g(vehs_test::seed(84));
  const double tau = uniform(g, 0.2, 1.0), intensity = uniform(g, 0.02, 0.06);
  run_loop({effect("colored_noise", {{"tau", tau}, {"intensity", intensity}}), bistable()}, 8401);
}

// The figures of bench/results/diagnose_calibration_log.md over random draws (not in CI, 20–35 s per draw):
//   VEHS_MP_DRAWS=electromechanical_coupling|colored_noise [VEHS_MP_N=6] [VEHS_MP_WEAK=1]
//   build/tests/test_diagnose "[explore_draws]"
// Draw s: parameters from mt19937_64(1000 + s) (λ in [0.6, 1.4], coupling in [0.6, 1.0] — with
// VEHS_MP_WEAK [0.3, 0.6] and 6000 samples instead of 10000; τ in [0.2, 1], intensity in
// [0.02, 0.06]), monostable and bistable alternating, data seed 20000 + s. Prints per draw the
// held-out leader, the suspect named first (after the confirmation) and whether the whole loop held.
TEST_CASE("missing physics loop over random draws", "[.][bench][explore_draws]") {
  const char* which = std::getenv("VEHS_MP_DRAWS");
  if (!which) return;
  const std::string kind = which;
  REQUIRE((kind == "electromechanical_coupling" || kind == "colored_noise"));
  const int n = std::getenv("VEHS_MP_N") ? std::atoi(std::getenv("VEHS_MP_N")) : 6;
  const bool weak = std::getenv("VEHS_MP_WEAK") != nullptr;
  int passed = 0, leader_hidden = 0, named_hidden = 0;
  for (int s = 0; s < n; ++s) {
    std::mt19937_64 g(1000 + static_cast<std::uint64_t>(s));
    const bool mono = s % 2 == 0;
    Hidden h;
    std::size_t samples = 6000;
    if (kind == "electromechanical_coupling") {
      const double lambda = uniform(g, 0.6, 1.4), c = weak ? uniform(g, 0.3, 0.6) : uniform(g, 0.6, 1.0);
      h = {effect(kind, {{"lambda", lambda}, {"coupling", c}}), mono ? monostable() : bistable()};
      samples = weak ? 6000 : 10000;
    } else {
      const double tau = uniform(g, 0.2, 1.0), intensity = uniform(g, 0.02, 0.06);
      h = {effect(kind, {{"tau", tau}, {"intensity", intensity}}), mono ? monostable() : bistable()};
    }
    const LoopOutcome o = run_loop(h, 20000 + static_cast<std::uint64_t>(s), samples);
    passed += o.ok;
    leader_hidden += o.heldout_leader == kind;
    named_hidden += o.named_first == kind;
    std::printf("draw %d (%s) %s: held-out leader %s, named first %s, loop %s\n", s, mono ? "monostable" : "bistable",
                vehs::effect_to_json(h.effect).dump().c_str(), o.heldout_leader.c_str(), o.named_first.c_str(),
                o.ok ? "passed" : "FAILED");
  }
  std::printf("%s: whole loop %d of %d; hidden effect the held-out leader %d, named first %d\n", kind.c_str(), passed,
              n, leader_hidden, named_hidden);
}

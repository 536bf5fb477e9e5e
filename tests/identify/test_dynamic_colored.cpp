// colored_noise (Ornstein–Uhlenbeck excitation) identified from continuous-time records (fine
// internal steps, exact OU update in the simulator) of two potentials, with tau and intensity
// drawn at random within physical ranges by the test; identify never sees them. Checks: tau and
// intensity within 3 standard errors and 15 % of the truth, the drift and the white diffusion
// within 3 standard errors (the IV refit removes the bias of the damping that the OU force,
// correlated with y, causes in least squares).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "identify_fixtures.hpp"
#include "vehs/core/error.hpp"
#include "vehs/identify/dynamic.hpp"

using namespace vehs;
using namespace vehs_test;

namespace {

}  // namespace

TEST_CASE("dynamic effects: colored_noise (OU time constant and intensity) on two potentials",
          "[identify][dynamic][colored]") {
  const std::string pot = GENERATE(std::string("bistable"), std::string("monostable"));
  std::mt19937_64 g(pot == "bistable" ? 91 : 92);
  Model truth = hidden_effect_potential(pot);
  Effect e;
  e.id = EffectId::ColoredNoise;
  e.params = {{"tau", uniform(g, 0.2, 1.0)}, {"intensity", uniform(g, 0.02, 0.06)}};
  truth.effects = {e};
  const Dataset d = simulate_hidden(truth, 5000 + g() % 1000, 8, 40000);
  identify::Options o;
  o.drift_library = {Term::parse("x"), Term::parse("x^3"), Term::parse("y")};
  o.diffusion_library = paper_diffusion_library(2);
  o.sparsity = identify::Sparsity::None;
  Effect req;
  req.id = EffectId::ColoredNoise;
  o.effects = {req};
  const identify::Result r = identify::identify(d, o);
  INFO(pot << ": " << model_to_json(r.model).dump());
  REQUIRE(r.model.effects.size() == 1);
  check_effect_param(r.model.effects[0], "tau", e.param("tau"));
  check_effect_param(r.model.effects[0], "intensity", e.param("intensity"));
  Model truth_terms = truth;
  truth_terms.effects.clear();
  const Deviation dev = compare(r.model, truth_terms);
  CHECK(dev.max_z <= 3.0);
}

TEST_CASE("calibration study: colored_noise over 10 seeds and both potentials (z of tau, intensity, damping; env CN_TAU, CN_INT, CN_SEEDS)",
          "[.calibration]") {
  const int seeds = std::getenv("CN_SEEDS") ? std::atoi(std::getenv("CN_SEEDS")) : 10;
  for (const std::string pot : {"bistable", "monostable"})
    for (int s = 0; s < seeds; ++s) {
      std::mt19937_64 g(static_cast<std::uint64_t>(200 + s));
      Model truth = hidden_effect_potential(pot);
      Effect e;
      e.id = EffectId::ColoredNoise;
      e.params = {{"tau", uniform(g, 0.2, 1.0)}, {"intensity", uniform(g, 0.02, 0.06)}};
      if (std::getenv("CN_TAU")) e.params["tau"] = std::atof(std::getenv("CN_TAU"));
      if (std::getenv("CN_INT")) e.params["intensity"] = std::atof(std::getenv("CN_INT"));
      truth.effects = {e};
      const Dataset d = simulate_hidden(truth, 7000 + static_cast<std::uint64_t>(s), 8, 40000);
      identify::Options o;
      o.drift_library = {Term::parse("x"), Term::parse("x^3"), Term::parse("y")};
      o.diffusion_library = paper_diffusion_library(2);
      o.sparsity = identify::Sparsity::None;
      Effect req;
      req.id = EffectId::ColoredNoise;
      o.effects = {req};
      const identify::Result r = identify::identify(d, o);
      const Effect& f = r.model.effects.at(0);
      auto z = [&](const char* k) { return (f.param(k) - e.param(k)) / f.stderr_.at(k); };
      auto rel = [&](const char* k) { return f.param(k) / e.param(k) - 1.0; };
      Model tt = truth;
      tt.effects.clear();
      const Deviation dev = compare(r.model, tt, false);
      std::printf("%s seed %d: tau %.3f z %+.2f rel %+.3f | intensity %.4f z %+.2f rel %+.3f | terms max_z %.2f (%s) | y %.4f +- %.4f a22_1 %.4f\n",
                  pot.c_str(), s, e.param("tau"), z("tau"), rel("tau"), e.param("intensity"), z("intensity"),
                  rel("intensity"), dev.max_z, dev.worst.c_str(), coefficient(r.model.drift, Term::parse("y")),
                  r.model.drift_stderr.at("y"), coefficient(r.model.diffusion, Term::parse("1")));
    }
}

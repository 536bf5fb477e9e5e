// The three standard-error methods of refine() on a well-specified model (the driven linear
// oscillator of test_filter, 3 records × 2000 samples): the observed information (Hessian by
// differences of the automatic gradient), the Fisher information of the innovations, and the
// sandwich over 200 batches agree; on the natural scale of a log-parameterised quantity the
// delta method holds (SE(2D) = 2D · SE(log 2D)).
#include <catch2/catch.hpp>

#include <cmath>

#include "likelihood_fixtures.hpp"
#include "vehs/likelihood/refine.hpp"
#include "vehs/likelihood/signals.hpp"

using namespace vehs;
using namespace vehs_lik_test;

// False-failure probability per run ≤ 1e-4: observed vs Fisher differ by O(n^-1/2) (≈ 1 %
// here; bound 10 %); the sandwich's relative sampling error with 200 batches is ≈ 1/√400 = 5 %
// per parameter, so the 30 % bound is 6 of its standard deviations (5 parameters: ≤ 1e-8).
TEST_CASE("observed, Fisher and sandwich standard errors agree on a well-specified model",
          "[likelihood][covariance]") {
  const Model truth = model(R"({"drift": {"x": -2.0, "y": -0.3, "u": 0.5}, "diffusion": {"1": 0.05}})");
  const double dt = 0.5;
  const auto u = likelihood::random_phase_multisine(4000, dt, 12, 0.25, 0.3, 5);
  const Dataset d = simulate(truth, dt, 3, 2000.0, 23, 0.03, 40, &u);
  likelihood::RefineOptions o;
  o.covariance = likelihood::Covariance::Observed;
  const auto obs = likelihood::refine({truth, 0.03, {}}, d, o);
  o.covariance = likelihood::Covariance::Fisher;
  const auto fis = likelihood::refine({truth, 0.03, {}}, d, o);
  o.covariance = likelihood::Covariance::Sandwich;
  o.sandwich_batch = d.x.size() / 200;
  const auto san = likelihood::refine({truth, 0.03, {}}, d, o);
  REQUIRE(obs.summary.covariance == "observed");
  REQUIRE(san.summary.covariance.rfind("sandwich", 0) == 0);
  for (std::size_t i = 0; i < obs.parameters.size(); ++i) {
    INFO(obs.parameters[i].name << ": observed " << obs.stderrs[i] << ", fisher " << fis.stderrs[i]
                                << ", sandwich " << san.stderrs[i]);
    CHECK(fis.stderrs[i] == Approx(obs.stderrs[i]).epsilon(0.10));
    CHECK(san.stderrs[i] == Approx(obs.stderrs[i]).epsilon(0.30));
    CHECK(obs.values[i] == Approx(fis.values[i]).epsilon(1e-6));
  }
  const int k = obs.find("diffusion[1]");
  REQUIRE(k >= 0);
  CHECK(obs.parameters[std::size_t(k)].log_scale);
  CHECK(obs.model.model.diffusion_stderr.at("1") == obs.stderrs[std::size_t(k)]);
}

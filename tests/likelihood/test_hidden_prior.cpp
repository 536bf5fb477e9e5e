// The block-start law of the hidden states (detail/hidden_prior.hpp): the electromechanical
// law's closed form without η, the linear model's stationary identities with η (both derived by
// hand, not by the code's Lyapunov solve), and the score at the truth unbiased on many blocks.
#include <catch2/catch.hpp>

#include <cmath>

#include "diagnose/score_fixtures.hpp"
#include "vehs/io/model_file.hpp"
#include "stat_bounds.hpp"
#include "vehs/likelihood/detail/hidden_prior.hpp"
#include "vehs/likelihood/score_test.hpp"

using namespace vehs;

namespace {

likelihood::detail::Coefficients<double> coefficients_of(const Model& m) {
  likelihood::detail::Coefficients<double> c;
  for (const auto& tc : m.drift) c.drift.push_back(tc.coef);
  for (const auto& tc : m.diffusion) c.diffusion.push_back(tc.coef);
  for (const Effect& e : m.effects) {
    if (e.id == EffectId::ElectromechanicalCoupling) c.lambda = e.param("lambda"), c.coupling = e.param("coupling");
    if (e.id == EffectId::ColoredNoise) c.tau = e.param("tau"), c.intensity = e.param("intensity");
  }
  return c;
}

}  // namespace

namespace {

/// The closed form of the law without η (the first fix's, 24 Nov; hidden_prior.hpp's header).
struct ClosedForm {
  double mean_v, var_v, var_y, cov_yv;
};
ClosedForm closed_form(double a, double b, double q, double f0, double kappa, double lambda) {
  const double g = 1.0 / (lambda + b + (a + kappa) / lambda);
  const double var_y = q / (2.0 * (b + kappa * g)), cov_yv = g * var_y, var_v = cov_yv / lambda;
  const double var_x = (var_y - kappa * var_v) / a, delta = -f0 / a;
  return {delta * var_v / var_x, var_v - var_v * var_v / var_x, var_y, cov_yv};
}

}  // namespace

TEST_CASE("hidden prior: without colored_noise it is the closed form of the electromechanical law",
          "[likelihood][hidden_prior]") {
  // a Duffing well with the coupling: at x0 the linearisation's a = −∂f/∂x, b = −∂f/∂y, f0
  const Model m = model_from_json(nlohmann::json::parse(
                                      R"({"drift": {"x": -1.0, "x^3": -0.5, "y": -0.15}, "diffusion": {"1": 0.03},
                                          "effects": [{"name": "electromechanical_coupling", "params": {"lambda": 0.8, "coupling": 0.4}}]})"),
                                  "coupled Duffing");
  const auto st = likelihood::detail::Structure::of(m, "test");
  const auto c = coefficients_of(m);
  for (double x0 : {-0.3, 0.0, 0.17, 1.5}) {
    const double a = 1.0 + 1.5 * x0 * x0, f0 = -x0 - 0.5 * x0 * x0 * x0;
    const ClosedForm e = closed_form(a, 0.15, 0.03, f0, 0.4, 0.8);
    likelihood::detail::HiddenPrior<double> h;
    REQUIRE(likelihood::detail::hidden_prior(st, c, x0, 1.0, h));
    CHECK(h.mean_v == Approx(e.mean_v).epsilon(1e-10).margin(1e-14));
    CHECK(h.var_v == Approx(e.var_v).epsilon(1e-10));
    CHECK(h.var_y == Approx(e.var_y).epsilon(1e-10));
    CHECK(h.cov_yv == Approx(e.cov_yv).epsilon(1e-10));
  }
}

// Stationarity of the linear oscillator dx = y, dy = −a x − b y + η + √q ξ, dη = −η/τ + …:
// d/dt E[xη] = 0 gives E[xη] = τ E[yη]; d/dt E[yη] = 0 gives E[yη] = Var η / (aτ + b + 1/τ);
// Var η = intensity / (2τ). (Derived by hand, not by the code's Lyapunov solve.)
TEST_CASE("hidden prior: the OU excitation's covariances with x and y", "[likelihood][hidden_prior]") {
  const double a = 1.3, b = 0.2, q = 0.01, tau = 0.6, intensity = 0.04;
  const Model m = model_from_json(nlohmann::json::parse(
                                      R"({"drift": {"x": -1.3, "y": -0.2}, "diffusion": {"1": 0.01},
                                          "effects": [{"name": "colored_noise", "params": {"tau": 0.6, "intensity": 0.04}}]})"),
                                  "linear OU");
  const auto st = likelihood::detail::Structure::of(m, "test");
  const auto c = coefficients_of(m);
  const double var_eta = intensity / (2 * tau), e_yeta = var_eta / (a * tau + b + 1 / tau), e_xeta = tau * e_yeta;
  // Var y: E[y²] b = q/2 + E[yη] (from d/dt E[y²] = 0 with E[xy] = 0)
  const double var_y = (q / 2 + e_yeta) / b;
  for (double x0 : {0.0, 0.4}) {
    likelihood::detail::HiddenPrior<double> h;
    REQUIRE(likelihood::detail::hidden_prior(st, c, x0, 1.0, h));
    CHECK(h.cov_yeta == Approx(e_yeta).epsilon(1e-10));  // Cov(x, y) = 0: conditioning leaves it
    CHECK(h.var_y == Approx(var_y).epsilon(1e-10));
    // E[η | x0] = E[xη]/Var x · δ with δ = x0 (equilibrium 0); Var x from d/dt E[xy] = 0:
    // E[y²] − a E[x²] + E[xη] = 0
    const double vx = (var_y + e_xeta) / a;
    CHECK(h.mean_eta == Approx(e_xeta / vx * x0).margin(1e-12));
    CHECK(h.var_eta == Approx(var_eta - e_xeta * e_xeta / vx).epsilon(1e-10));
  }
}

// The colored_noise case of issue 13 (bistable, OU intensity 0.04, τ 0.6, 2D 0.01; seed 100):
// the score test of electromechanical_coupling at λ 5.2 on the TRUE model (what diagnose's
// suspects run on a refit with colored_noise). Before (η started independent of y, v's law
// from the white noise alone): z 6–12 at 32 × 4000 samples, 18.8 at 128 × 1000 (the shift grew
// with the blocks); after: z −0.1 … 2.2 over seeds and shapes. One N(0, 1) statistic: |z| < 4.42
// (false failure 1e-5).
TEST_CASE("hidden prior: the electromechanical score at the true colored_noise model is unbiased "
          "on many short records", "[likelihood][hidden_prior]") {
  score_test::HiddenCase c;
  for (const auto& h : score_test::hidden_cases())
    if (h.name == "colored_noise") c = h;
  c.records = 128;
  c.samples = 1000;
  const Dataset d = score_test::hidden_data(c, 100);
  Model m = score_test::truth_of(c);
  Effect e;
  e.id = EffectId::ElectromechanicalCoupling;
  e.params = {{"coupling", 0.0}, {"lambda", 5.209}};
  m.effects.push_back(e);
  likelihood::ScoreTestOptions o;
  o.fixed = {"electromechanical_coupling.lambda"};
  const auto r = likelihood::score_test({m, 0.0, {}}, d, {"electromechanical_coupling.coupling"}, o);
  INFO("z " << r.z);
  CHECK(std::abs(r.z) < vehs_test::z_bound(1, 1e-5));
}

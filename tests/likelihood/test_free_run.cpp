// Free-run simulation against exact solutions: a damped linear oscillator from an initial state
// (closed form), and the same driven by a held input (exact discretisation by the matrix
// exponential of the augmented system); the validation scores.
#include <catch2/catch.hpp>

#include <unsupported/Eigen/MatrixFunctions>

#include <cmath>

#include "likelihood_fixtures.hpp"
#include "vehs/likelihood/free_run.hpp"

using namespace vehs;
using namespace vehs_lik_test;

TEST_CASE("free run of a damped linear oscillator equals the closed-form solution", "[likelihood][free_run]") {
  // ẍ = −ω² x − 2ζω ẋ, x(0) = 1, ẋ(0) = 0
  const double w = 1.3, zeta = 0.1, wd = w * std::sqrt(1 - zeta * zeta), dt = 0.5;
  const Model m = model(R"({"drift": {"x": -1.69, "y": -0.26}, "diffusion": {"1": 0.0}})");
  likelihood::FreeRunOptions o;
  o.substeps = 16;
  const auto x = likelihood::free_run(m, {1.0, 0.0}, {}, dt, 200, o);
  double worst = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    const double t = dt * double(k);
    const double exact = std::exp(-zeta * w * t) * (std::cos(wd * t) + zeta * w / wd * std::sin(wd * t));
    worst = std::max(worst, std::abs(x[k] - exact));
  }
  CHECK(worst < 1e-7);
}

TEST_CASE("free run with a held input equals the exact discretisation, and its validation scores",
          "[likelihood][free_run]") {
  const Model m = model(R"({"drift": {"x": -2.0, "y": -0.3, "u": 0.5}, "diffusion": {"1": 0.0}})");
  const double dt = 0.4;
  std::vector<double> u(300);
  for (std::size_t i = 0; i < u.size(); ++i) u[i] = std::sin(0.37 * double(i)) + 0.3 * std::cos(1.9 * double(i));
  Eigen::Matrix3d aug = Eigen::Matrix3d::Zero();
  aug(0, 1) = 1.0;
  aug(1, 0) = -2.0;
  aug(1, 1) = -0.3;
  aug(1, 2) = 0.5;
  const Eigen::Matrix3d E = (aug * dt).exp();
  Eigen::Vector3d s(0.2, -0.1, 0.0);
  std::vector<double> exact(u.size());
  for (std::size_t k = 0; k < u.size(); ++k) {
    exact[k] = s[0];
    s[2] = u[k];
    s = E * s;
  }
  likelihood::FreeRunOptions o;
  o.substeps = 32;
  const auto x = likelihood::free_run(m, {0.2, -0.1}, u, dt, u.size(), o);
  for (std::size_t k = 0; k < x.size(); ++k) CHECK(x[k] == Approx(exact[k]).margin(1e-8));
  // validation of the exact output from its exact initial state scores 0
  const auto v = likelihood::validate_free_run(m, exact, u, dt, 10, o, likelihood::InitialState{0.2, -0.1});
  CHECK(v.rmse < 1e-8);
  CHECK(v.simulated.size() == exact.size());
  CHECK(v.measured_rms > 0.05);
}

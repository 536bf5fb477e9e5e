// The filter's stiff fallback (vehs/likelihood/detail/implicit_step.hpp) against exact solutions:
// backward Euler on the moment equations of a linear oscillator converges to the closed-form mean
// and covariance at first order, keeps the covariance valid where no RK4 count does, carries
// derivatives equal to those of its own values; and the filter over nearly deterministic motion
// with Coulomb friction (the positioning rig of issue 33) gives a number instead of diverging.
//
// Exact reference: for dX = Y dt, dY = (−k X − β Y) dt + √q dB the mean is e^{At} m₀ and the
// covariance P∞ + e^{At} (P₀ − P∞) e^{Aᵀt}, with the stationary P∞ = diag(q/2kβ, q/2β).
#include <catch2/catch.hpp>

#include <unsupported/Eigen/MatrixFunctions>

#include <ceres/jet.h>

#include <cmath>
#include <string>
#include <vector>

#include "likelihood_fixtures.hpp"
#include "vehs/likelihood/detail/block_filter.hpp"
#include "vehs/likelihood/detail/implicit_step.hpp"
#include "vehs/likelihood/filter.hpp"
#include "vehs/likelihood/signals.hpp"

using namespace vehs;
using namespace vehs_lik_test;
namespace lik = vehs::likelihood::detail;

namespace {

using State = lik::PackedState<double, 2>;
using Pk = lik::Packing<2>;

struct Linear {
  double k, beta, q;
  Model as_model() const {
    Model m;
    m.drift = {{Term::monomial(1, 0), -k}, {Term::monomial(0, 1), -beta}};
    m.diffusion = {{Term::monomial(0, 0), q}};
    return m;
  }
  /// Mean and covariance after time t from (m0, P0), packed as the filter packs them.
  State exact(const State& s0, double t) const {
    Eigen::Matrix2d A;
    A << 0, 1, -k, -beta;
    const Eigen::Matrix2d Phi = (A * t).exp();
    Eigen::Matrix2d Pinf = Eigen::Matrix2d::Zero();
    Pinf(0, 0) = q / (2.0 * k * beta);
    Pinf(1, 1) = q / (2.0 * beta);
    Eigen::Matrix2d P0;
    P0 << s0[Pk::p(0, 0)], s0[Pk::p(0, 1)], s0[Pk::p(0, 1)], s0[Pk::p(1, 1)];
    const Eigen::Vector2d m = Phi * Eigen::Vector2d(s0[0], s0[1]);
    const Eigen::Matrix2d P = Pinf + Phi * (P0 - Pinf) * Phi.transpose();
    State s;
    s << m[0], m[1], P(0, 0), P(0, 1), P(1, 1);
    return s;
  }
};

/// Coefficients of the structure's terms from the model (the linear model has no effects).
template <class T>
lik::Coefficients<T> coefficients(const lik::Structure& st, const Model& m) {
  lik::Coefficients<T> c;
  for (const Term& t : st.drift) c.drift.push_back(T(m.drift_coef(t.name())));
  for (const Term& t : st.diffusion) c.diffusion.push_back(T(m.diffusion_coef(t.name())));
  return c;
}

State start_state() {
  State s;
  s << 1.0, -0.5, 0.04, 0.01, 0.09;
  return s;
}

/// Backward Euler over [0, t] in `steps` steps of the linear model.
bool implicit(const Linear& lin, double t, int steps, State& s) {
  const Model m = lin.as_model();
  const lik::Structure st = lik::Structure::of(m, "test");
  const auto c = coefficients<double>(st, m);
  lik::MomentSystem<double, 2> sys(st, c);
  sys.set_drive(0.0, t, {});
  lik::ImplicitPropagator<double, 2> ip(st, c);
  return ip.propagate(sys, 0.0, t, steps, {}, s);
}

double max_relative_error(const State& a, const State& b) {
  double e = 0.0;
  for (int j = 0; j < Pk::size; ++j) e = std::max(e, std::abs(a[j] - b[j]) / std::max(std::abs(b[j]), 1e-12));
  return e;
}

}  // namespace

TEST_CASE("backward Euler on the moment equations converges at first order to the exact law",
          "[likelihood][implicit]") {
  const Linear lin{4.0, 0.3, 0.5};
  const State exact = lin.exact(start_state(), 1.0);
  double previous = 0.0;
  for (const int steps : {200, 400, 800, 1600}) {
    State s = start_state();
    REQUIRE(implicit(lin, 1.0, steps, s));
    const double err = max_relative_error(s, exact);
    INFO(steps << " steps: largest relative error " << err);
    CHECK(err < 2.0 / steps * 10.0);
    if (previous > 0.0) {
      // first order: doubling the steps halves the error (ratio 2 up to O(h) corrections)
      CHECK(previous / err > 1.8);
      CHECK(previous / err < 2.2);
    }
    previous = err;
  }
}

TEST_CASE("backward Euler keeps a valid covariance where no RK4 count holds", "[likelihood][implicit]") {
  // damping 1e5 over an interval of 1: RK4 with 4 × 64 substeps has beta·h = 390, far beyond its
  // stability bound 2.8; the exact law is near its quasi-stationary state P_yy = q/2β
  const Linear lin{1.0, 1e5, 2.0};
  const Model m = lin.as_model();
  const lik::Structure st = lik::Structure::of(m, "test");
  const auto c = coefficients<double>(st, m);
  lik::MomentSystem<double, 2> sys(st, c);
  sys.set_drive(0.0, 1.0, {});
  State rk = start_state();
  long long work = 0;
  CHECK_FALSE(lik::propagate_interval<double, 2>(sys, 0.0, 1.0, 4, 0.0, rk, work));
  CHECK(work == 4 * (1 + 4 + 16 + 64));
  State s = start_state();
  REQUIRE(implicit(lin, 1.0, 16, s));
  CHECK(lik::valid_covariance<double, 2>(s, 0.0));
  const State exact = lin.exact(start_state(), 1.0);
  INFO("P_yy " << s[Pk::p(1, 1)] << " exact " << exact[Pk::p(1, 1)] << "; m_x " << s[0] << " exact " << exact[0]);
  CHECK(std::abs(s[Pk::p(1, 1)] / exact[Pk::p(1, 1)] - 1.0) < 1e-3);
  CHECK(std::abs(s[0] / exact[0] - 1.0) < 1e-4);
  CHECK(std::abs(s[Pk::p(0, 0)] / exact[Pk::p(0, 0)] - 1.0) < 1e-3);
}

TEST_CASE("the implicit step's derivatives are those of its values", "[likelihood][implicit]") {
  // d(state after the step)/d(beta) carried as a Jet against a central difference of the values
  using J = ceres::Jet<double, 1>;
  const Linear lin{4.0, 30.0, 0.5};
  const Model m = lin.as_model();
  const lik::Structure st = lik::Structure::of(m, "test");
  auto cj = coefficients<J>(st, m);
  for (std::size_t j = 0; j < st.drift.size(); ++j)
    if (st.drift[j].name() == "y") cj.drift[j].v[0] = 1.0;  // d/d(drift[y])
  lik::MomentSystem<J, 2> sys(st, cj);
  sys.set_drive(0.0, 0.5, {});
  lik::ImplicitPropagator<J, 2> ip(st, cj);
  lik::PackedState<J, 2> sj;
  const State s0 = start_state();
  for (int j = 0; j < Pk::size; ++j) sj[j] = J(s0[j]);
  REQUIRE(ip.propagate(sys, 0.0, 0.5, 8, {}, sj));
  const double h = 1e-5;
  State plus = s0, minus = s0;
  REQUIRE(implicit({lin.k, lin.beta - h, lin.q}, 0.5, 8, plus));  // drift[y] = −beta: +h
  REQUIRE(implicit({lin.k, lin.beta + h, lin.q}, 0.5, 8, minus));
  for (int j = 0; j < Pk::size; ++j) {
    const double fd = (plus[j] - minus[j]) / (2.0 * h);
    INFO("component " << j << ": Jet " << sj[j].v[0] << ", central difference " << fd);
    CHECK(std::abs(sj[j].a - (plus[j] + minus[j]) / 2.0) < 1e-9 * (1.0 + std::abs(plus[j])));
    CHECK(std::abs(sj[j].v[0] - fd) < 1e-5 * (std::abs(fd) + 1e-6));
  }
}

TEST_CASE("the filter holds on nearly deterministic motion with Coulomb friction", "[likelihood][implicit]") {
  // a positioning axis: strong friction (0.21) against a held force that starts and stops the
  // motion, force noise √2.8e-9 and a sensor resolution of 1e-8: while the axis sticks the
  // velocity is known to ~1e-8, Coulomb's expected slope μ·2φ(0)/√P_yy is ~1e7 and explicit
  // steps leave the domain at every count (without the implicit fallback the filter diverges
  // at sample 569)
  const double r = 1e-8;
  const Model rig = model(
      R"J({"drift": {"1": -0.0316, "y": -2.1, "sign(y)": -0.21, "u": 0.0105}, "diffusion": {"1": 2.8e-9}})J");
  std::vector<double> u(6000);
  for (std::size_t k = 0; k < u.size(); ++k) {
    const std::size_t phase = (k / 300) % 4;
    u[k] = phase == 0 ? 60.0 : phase == 2 ? -60.0 : 0.0;
  }
  sim::SimulationOptions o;
  o.dt = 1e-3;
  o.substeps = 40;
  o.samples = u.size();
  o.seed = 7;
  o.scheme = sim::Scheme::Taylor15;
  o.sensor_noise = r;
  o.record_y = false;
  o.allow_unconfined = true;  // the held force moves the axis; nothing pulls it back
  o.drive = u;
  const Dataset d = sim::simulate(rig, o);
  const likelihood::ObservedModel om{rig, r, {}};
  const auto v = likelihood::log_likelihood(om, d);
  INFO("log L " << v.log_likelihood << " with " << v.substeps << " substeps");
  CHECK(std::isfinite(v.log_likelihood));
  // the innovations are of the sensor's size: the filter tracks the motion
  CHECK(v.log_likelihood / double(v.observations) > 10.0);
}

namespace {

/// The filter's error on 640 unit intervals of a linear oscillator's record for the damping
/// `beta` and a weak friction 0.01·sign(y) (the fallback and its bounds are for models with
/// friction; the friction's slope is small beside beta here), with `substeps` planned RK4
/// substeps per interval ("" when it runs through).
std::string stiff_failure(double beta, int substeps) {
  const Dataset d = simulate(Linear{1.0, 1.0, 2.0}.as_model(), 1.0, 1, 640.0, 5);
  likelihood::FilterOptions f;
  f.substeps = substeps;
  Model m = Linear{1.0, beta, 2.0}.as_model();
  m.drift.push_back({Term::sign_y(), -0.01});
  try {
    const double ll = likelihood::log_likelihood({m, 0.0, {}}, d, f).log_likelihood;
    return std::isfinite(ll) ? "" : "log L not finite";
  } catch (const Error& e) {
    return e.what();
  }
}

}  // namespace

TEST_CASE("a model stiff on every interval is refused as diverged after a bounded share of them",
          "[likelihood][implicit]") {
  // damping 1e5 against four RK4 substeps per unit interval: every interval needs the implicit
  // fallback, which the filter allows on 8 + n/32 of a block's n intervals (implicit_budget): it
  // stops there instead of paying implicit steps along the whole record
  const std::size_t budget = lik::implicit_budget(640);
  CHECK(budget == 8 + 640 / 32);
  const std::string what = stiff_failure(1e5, 4);
  INFO(what);
  CHECK(what.find("implicit steps on more intervals than the filter allows") != std::string::npos);
  CHECK(what.find("at sample " + std::to_string(budget + 1) + " ") != std::string::npos);
}

TEST_CASE("a model that needs finer RK4 steps on every interval is refused at the cost bound",
          "[likelihood][implicit]") {
  // damping 100 against four RK4 substeps per unit interval: the covariance's fastest rate is
  // 2·beta = 200, beyond RK4's real stability bound 2.79 at 4, 16 and 64 substeps (h·200 = 50,
  // 12.5, 3.1) and within it at 256 (0.78): 340 substeps spent where 4 were planned, on every
  // interval. The filter stops once a block has spent 10 × its planned substeps: after interval
  // k with 340·k > 10·640·4, k = 76
  const std::string what = stiff_failure(100.0, 4);
  INFO(what);
  CHECK(what.find("cost bound") != std::string::npos);
  CHECK(what.find("at sample 76 ") != std::string::npos);
  // with the substeps it needs, the same model is filtered through
  CHECK(stiff_failure(100.0, 256) == "");
}

// The steppers of vehs/sim/steppers.hpp are generic: systems written here — not the simulator's
// model — run through them, with one trajectory or with lanes, over double or another scalar
// type, and reproduce exact results.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "vehs/sim/random.hpp"
#include "vehs/sim/steppers.hpp"

using namespace vehs::sim;

namespace {

constexpr int kLanes = 8;

/// dX = −θ X dt + σ dW on lanes (a first-order system).
struct OrnsteinUhlenbeckLanes {
  using Lanes = Eigen::Array<double, kLanes, 1>;
  using State = Eigen::Array<double, kLanes, 1>;
  using Noise = Eigen::Array<double, kLanes, 1>;
  static constexpr int noises = 1;
  static constexpr int noise_component(int) { return 0; }
  double theta = 1.0, sigma = 1.0;
  void drift(double, const State& s, State& f) const { f = -theta * s; }
  void noise(const State&, Noise& g) const { g.setConstant(sigma); }
};

/// The same process, one trajectory (Lanes a scalar: components are entries).
struct OrnsteinUhlenbeck {
  using Lanes = double;
  using State = Eigen::Array<double, 1, 1>;
  using Noise = Eigen::Array<double, 1, 1>;
  static constexpr int noises = 1;
  static constexpr int noise_component(int) { return 0; }
  double theta = 1.0, sigma = 1.0;
  void drift(double, const State& s, State& f) const { f = -theta * s; }
  void noise(const State&, Noise& g) const { g(0) = sigma; }
};

/// A damped harmonic oscillator dx = y dt, dy = (−k x − β y) dt + σ dW on lanes (mechanical).
struct HarmonicOscillator {
  using Lanes = Eigen::Array<double, kLanes, 1>;
  using State = Eigen::Array<double, kLanes, 2>;
  using Noise = Eigen::Array<double, kLanes, 1>;
  static constexpr int noises = 1;
  static constexpr int hidden = 0;
  static constexpr int noise_component(int) { return 1; }
  double k = 1.0, beta = 0.5, sig = 1.0;
  Lanes b2(double, const State& s) const { return -k * s.col(0) - beta * s.col(1); }
  void drift(double t, const State& s, State& f) const {
    f.col(0) = s.col(1);
    f.col(1) = b2(t, s);
  }
  void noise(const State&, Noise& g) const { g.setConstant(sig); }
  Lanes sigma(const State&) const { return Lanes::Constant(sig); }
  double linear_damping() const { return beta; }
  Lanes force_nl(double t, const State& s) const { return b2(t, s) + beta * s.col(1); }
  bool noise_depends_on_y() const { return false; }
  LinearHidden hidden_state(int) const { return {}; }
  TaylorDerivatives<Lanes> derivatives(double t, const State& s) const {
    TaylorDerivatives<Lanes> j;
    j.b2 = b2(t, s);
    j.b2_x = Lanes::Constant(-k);
    j.b2_y = Lanes::Constant(-beta);
    j.b2_yy = j.b2_t = j.sigma_x = j.sigma_y = j.sigma_yy = Lanes::Zero();
    j.sigma = Lanes::Constant(sig);
    return j;
  }
};

/// Sample variance of component 0 over `records` independent trajectories after `steps` steps
/// from 0 (long enough to forget the start), with its standard error Var·sqrt(2/(n − 1))
/// (Gaussian values).
template <class Stepper, class System>
std::pair<double, double> lane_variance(const System& sys, double h, int steps, int records) {
  using State = typename System::State;
  const CounterRng rng(2024);
  double s1 = 0.0, s2 = 0.0;
  for (int b = 0; b < records / kLanes; ++b) {
    State s = State::Zero();
    for (int n = 0; n < steps; ++n) {
      Eigen::Array<double, kLanes, Stepper::normals_per_source> xi;
      for (int l = 0; l < kLanes; ++l)
        for (int c = 0; c < Stepper::normals_per_source; ++c)
          xi(l, c) = rng.normal(static_cast<std::uint64_t>(b * kLanes + l), Purpose::User,
                                static_cast<std::uint64_t>(Stepper::normals_per_source * n + c));
      Stepper().step(sys, s, n * h, h, xi);
    }
    for (int l = 0; l < kLanes; ++l) s1 += s(l, 0), s2 += s(l, 0) * s(l, 0);
  }
  const double n = records;
  const double var = (s2 - s1 * s1 / n) / (n - 1.0);
  return {var, var * std::sqrt(2.0 / (n - 1.0))};
}

/// A dual number a + b ε (ε² = 0): enough arithmetic to be the state of an ODE.
struct Dual {
  double a = 0.0, b = 0.0;
};
Dual operator+(Dual x, Dual y) { return {x.a + y.a, x.b + y.b}; }
Dual operator*(double c, Dual x) { return {c * x.a, c * x.b}; }
Dual operator*(Dual x, Dual y) { return {x.a * y.a, x.a * y.b + x.b * y.a}; }
Dual& operator+=(Dual& x, Dual y) { return x = x + y; }

/// ds/dt = −λ s with λ a dual number (its ε part carries d/dλ).
template <class Scalar>
struct Decay {
  Scalar lambda;
  void drift(double, const Scalar& s, Scalar& f) const { f = (-1.0) * (lambda * s); }
};

}  // namespace

TEST_CASE("Euler-Maruyama on a user's OU system reaches the scheme's exact stationary variance",
          "[sim][steppers]") {
  // x_{n+1} = (1 − θh) x_n + σ√h ξ: Var = σ²h / (1 − (1 − θh)²) = σ² / (θ(2 − θh)) exactly (0.5556
  // at θh = 0.2, against 0.5 of the continuous process). 65536 independent Gaussian values: the
  // sample variance is within 4.42 standard errors with probability 1 − 1e-5.
  const double h = 0.2;
  OrnsteinUhlenbeckLanes lanes;
  const double exact = lanes.sigma * lanes.sigma / (lanes.theta * (2.0 - lanes.theta * h));
  const auto [var, se] = lane_variance<EulerMaruyamaStepper>(lanes, h, 150, 65536);
  CAPTURE(var, se, exact);
  CHECK(std::abs(var - exact) < 4.42 * se);
  CHECK(std::abs(var - 0.5) > 10.0 * se);  // the test tells the scheme from the continuous process

  // one trajectory at a time (Lanes = double): the same numbers, entry by entry
  OrnsteinUhlenbeck one;
  const CounterRng rng(2024);
  for (int record = 0; record < 8; ++record) {
    OrnsteinUhlenbeck::State s = OrnsteinUhlenbeck::State::Zero();
    OrnsteinUhlenbeckLanes::State sl = OrnsteinUhlenbeckLanes::State::Zero();
    for (int n = 0; n < 20; ++n) {
      Eigen::Array<double, 1, 1> xi;
      xi(0) = rng.normal(static_cast<std::uint64_t>(record), Purpose::User, static_cast<std::uint64_t>(n));
      EulerMaruyamaStepper().step(one, s, n * h, h, xi);
      Eigen::Array<double, kLanes, 1> xil = Eigen::Array<double, kLanes, 1>::Constant(xi(0));
      EulerMaruyamaStepper().step(lanes, sl, n * h, h, xil);
    }
    CHECK(s(0) == sl(3));
  }
}

TEST_CASE("the paper's RK4 + Euler (Eq. 30) on a user's OU system: Var = σ²h / (1 − R(−θh)²)",
          "[sim][steppers]") {
  // RK4 makes the deterministic factor R(z) = 1 + z + z²/2 + z³/6 + z⁴/24, z = −θh; the Euler
  // noise is added after it: Var = σ²h / (1 − R²) exactly. Probability of a false failure 1e-5.
  const double h = 0.5;
  OrnsteinUhlenbeckLanes lanes;
  const double z = -lanes.theta * h;
  const double R = 1 + z + z * z / 2 + z * z * z / 6 + z * z * z * z / 24;
  const double exact = lanes.sigma * lanes.sigma * h / (1.0 - R * R);
  const auto [var, se] = lane_variance<Rk4EulerStepper>(lanes, h, 80, 65536);
  CAPTURE(var, se, exact);
  CHECK(std::abs(var - exact) < 4.42 * se);
}

TEST_CASE("BAOAB on a user's harmonic oscillator samples positions exactly: E[X²] = σ²/(2βk)",
          "[sim][steppers]") {
  // BAOAB's configurational sampling of a harmonic potential is exact at any stable step
  // (Leimkuhler & Matthews 2013): E[X²] = kT/k with kT = σ²/(2β), here 1.0 at h = 0.4. Independent
  // Gaussian end points: a false failure has probability 1e-5.
  HarmonicOscillator osc;
  const double exact = osc.sig * osc.sig / (2.0 * osc.beta * osc.k);
  const auto [var, se] = lane_variance<BaoabStepper>(osc, 0.4, 300, 65536);
  CAPTURE(var, se, exact);
  CHECK(std::abs(var - exact) < 4.42 * se);
  // Taylor 1.5 runs the same system (its bias at this step is O(h²): a few per cent)
  const auto [tvar, tse] = lane_variance<Taylor15Stepper>(osc, 0.1, 1000, 8192);
  CAPTURE(tvar, tse);
  CHECK(std::abs(tvar - exact) < 0.05 * exact + 4.42 * tse);
}

TEST_CASE("Rk4 is generic over the state and scalar type: fourth order on doubles, derivatives on duals",
          "[sim][steppers]") {
  // ds/dt = −λ s, s(0) = 1: s(1) = e^{−λ}; RK4's global error falls 16-fold per halving of h
  auto solve = [](auto sys, auto s, int n) {
    const double h = 1.0 / n;
    for (int i = 0; i < n; ++i) Rk4().do_step(sys, s, i * h, h);
    return s;
  };
  const double lambda = 1.3;
  const double e16 = std::abs(solve(Decay<double>{lambda}, 1.0, 16) - std::exp(-lambda));
  const double e32 = std::abs(solve(Decay<double>{lambda}, 1.0, 32) - std::exp(-lambda));
  CHECK(std::log2(e16 / e32) == Approx(4.0).margin(0.05));
  // with a dual number for λ the same code propagates d/dλ: the derivative of the discrete
  // solution, which converges to d/dλ e^{−λ} = −e^{−λ}
  const Dual s = solve(Decay<Dual>{Dual{lambda, 1.0}}, Dual{1.0, 0.0}, 64);
  CHECK(s.a == solve(Decay<double>{lambda}, 1.0, 64));
  const double fd = (solve(Decay<double>{lambda + 1e-6}, 1.0, 64) - solve(Decay<double>{lambda - 1e-6}, 1.0, 64)) / 2e-6;
  CHECK(s.b == Approx(fd).epsilon(1e-8));
  CHECK(s.b == Approx(-std::exp(-lambda)).epsilon(1e-6));
}

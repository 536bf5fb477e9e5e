// A system vehs knows nothing about, run through its generic steppers (vehs/sim/steppers.hpp),
// with a strong-convergence check: a Duffing oscillator with parametric (multiplicative) noise,
//     dx = y dt,   dy = (-gamma y - alpha x - delta x^3) dt + sigma x dW,
// written as the user's own struct with its own state type (a fixed-size Eigen array).
// Each path is integrated at steps h = T/N and, on the same Brownian path, at h/64 (the
// reference); the strong error E|x_h(T) - x_ref(T)| should fall as h^1 for both Euler-Maruyama
// and the paper's RK4-Euler (the noise amplitude depends on x only, so the Milstein correction
// sigma x * d(sigma x)/dy vanishes and both are strong order 1). Exit status 0 when both
// measured orders lie in [0.8, 1.2]. Fixed seed: the output is deterministic.
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <Eigen/Core>

#include <vehs/sim/steppers.hpp>

// The system concept of a first-order SDE (steppers.hpp): types, noise count, drift, noise.
struct NoisyDuffing {
  using State = Eigen::Array2d;  // (x, y): one trajectory
  using Noise = Eigen::Array<double, 1, 1>;
  using Lanes = double;  // one trajectory per state (a column type would run lanes)
  static constexpr int noises = 1;
  static constexpr int noise_component(int) { return 1; }  // dW drives y

  double gamma = 0.2, alpha = -1.0, delta = 1.0, sigma = 0.3;  // bistable: wells at x = +-1

  void drift(double /*t*/, const State& s, State& f) const {
    f(0) = s(1);
    f(1) = -gamma * s(1) - alpha * s(0) - delta * s(0) * s(0) * s(0);
  }
  void noise(const State& s, Noise& g) const { g(0) = sigma * s(0); }
};

// x(T) on `steps` steps of size T/steps from the Brownian increments dW of the finest grid.
template <class Stepper>
double integrate(const NoisyDuffing& sys, const std::vector<double>& dW, int fine_per_step, int steps, double T) {
  const Stepper stepper;
  const double h = T / steps;
  NoisyDuffing::State s(1.0, 0.0);
  NoisyDuffing::Noise xi;
  for (int n = 0; n < steps; ++n) {
    double w = 0.0;  // the Wiener increment over this step, aggregated exactly
    for (int k = 0; k < fine_per_step; ++k) w += dW[static_cast<std::size_t>(n * fine_per_step + k)];
    xi(0) = w / std::sqrt(h);  // the steppers take standard normals: dW = sqrt(h) xi
    stepper.step(sys, s, n * h, h, xi);
  }
  return s(0);
}

template <class Stepper>
double measured_order(const char* name, const NoisyDuffing& sys) {
  const double T = 1.0;
  const int paths = 400, refine = 64;
  const std::vector<int> steps = {16, 32, 64, 128};
  const int fine = steps.back() * refine;
  std::vector<double> error(steps.size(), 0.0);
  std::mt19937_64 rng(2024);
  std::normal_distribution<double> normal;
  std::vector<double> dW(static_cast<std::size_t>(fine));
  for (int p = 0; p < paths; ++p) {
    for (double& w : dW) w = std::sqrt(T / fine) * normal(rng);
    const double reference = integrate<Stepper>(sys, dW, 1, fine, T);
    for (std::size_t i = 0; i < steps.size(); ++i)
      error[i] += std::abs(integrate<Stepper>(sys, dW, fine / steps[i], steps[i], T) - reference) / paths;
  }
  // least-squares slope of log(error) over log(h)
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double m = static_cast<double>(steps.size());
  std::printf("%s\n  %8s  %12s\n", name, "h", "E|x_h - x_ref|");
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const double lh = std::log(T / steps[i]), le = std::log(error[i]);
    sx += lh, sy += le, sxx += lh * lh, sxy += lh * le;
    std::printf("  %8.5f  %12.4e\n", T / steps[i], error[i]);
  }
  const double order = (m * sxy - sx * sy) / (m * sxx - sx * sx);
  std::printf("  measured strong order %.2f (expected 1)\n", order);
  return order;
}

int main() {
  const NoisyDuffing sys;
  const double em = measured_order<vehs::sim::EulerMaruyamaStepper>("Euler-Maruyama", sys);
  const double rk = measured_order<vehs::sim::Rk4EulerStepper>("RK4-Euler (the paper's Eq. 30)", sys);
  const bool ok = em > 0.8 && em < 1.2 && rk > 0.8 && rk < 1.2;
  std::printf("%s\n", ok ? "convergence check passed" : "convergence check FAILED");
  return ok ? 0 : 1;
}

// Convergence of every stepper, written once (TEMPLATE_TEST_CASE) and run for each:
//  * strong order on a ladder of steps, against a fine Taylor-1.5 reference driven by the same
//    Brownian path (coarse increments ΔW, ΔZ are aggregated exactly from the fine ones);
//  * long-run weak bias of E[Y²] against exact values (Q = 0: Gibbs density, E[Y²] = D/β for any
//    potential; Q > 0: energy balance β·E[Y²] = D + Q·E[X²]).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <vector>

#include "vehs/io/model_file.hpp"
#include "vehs/sim/random.hpp"
#include "vehs/sim/simulate.hpp"
#include "vehs/sim/steppers.hpp"
#include "stat_bounds.hpp"
#include "vehs/sim/detail/model_system.hpp"

using namespace vehs::sim;
using vehs::sim::detail::CompiledModel;
using vehs::sim::detail::ModelSystem;
using vehs::sim::detail::PolynomialSystem;

namespace {

constexpr int L = 8;

vehs::Model model_of(const char* json) { return vehs::model_from_json(nlohmann::json::parse(json), "test model"); }

/// The errors of one ladder: e²_i(H) = (X_H − X_ref)² + (Y_H − Y_ref)² at time T of path i for
/// each coarse step H = T / 2^k, k in [k_min, k_max], every path and level driven by the same
/// Brownian path (common random numbers).
struct LadderErrors {
  std::vector<double> rms;               ///< sqrt(mean_i e²_i(H)) per level: the strong (L²) error
  std::vector<std::vector<double>> log;  ///< ½·log e²_i(H): log[level][path]
};

/// The ladder's errors; reference: Taylor 1.5 with h = T / 2^k_ref.
template <class Stepper, class System>
LadderErrors strong_errors(const CompiledModel& cm, double x0, double y0, int k_min, int k_max, int k_ref,
                           int batches) {
  constexpr int S = System::noises;
  using State = typename System::State;
  using Lanes = typename System::Lanes;
  const double T = 1.0;
  const int n_fine = 1 << k_ref;
  const double h = T / n_fine;
  const auto levels = static_cast<std::size_t>(k_max - k_min + 1);
  std::vector<double> sq(levels, 0.0);
  LadderErrors out;
  out.log.assign(levels, std::vector<double>());
  const CounterRng rng(vehs_test::seed(77));
  for (int b = 0; b < batches; ++b) {
    System sys(cm);
    std::array<std::uint32_t, L> ids{};
    for (int l = 0; l < L; ++l) ids[static_cast<std::size_t>(l)] = static_cast<std::uint32_t>(b * L + l);
    // fine normals: step k, source j -> (ξ1, ξ2) = normals 2(kS + j), 2(kS + j) + 1
    std::vector<double> z(static_cast<std::size_t>(2 * n_fine * S * L));
    fill_normals<L>(rng, ids, Purpose::User, 0, n_fine * S, z.data());
    auto xi_fine = [&](int k, int j, int which) {
      return Eigen::Map<const Lanes>(z.data() + static_cast<std::size_t>((2 * (k * S + j) + which) * L));
    };
    State init = State::Zero();
    init.col(0).setConstant(x0);
    init.col(1).setConstant(y0);
    // reference
    State ref = init;
    const Taylor15Stepper taylor;
    for (int k = 0; k < n_fine; ++k) {
      Eigen::Array<double, L, 2 * S> xi;
      for (int j = 0; j < S; ++j) {
        xi.col(2 * j) = xi_fine(k, j, 0);
        xi.col(2 * j + 1) = xi_fine(k, j, 1);
      }
      taylor.step(sys, ref, k * h, h, xi);
    }
    // coarse ladder
    for (int level = k_min; level <= k_max; ++level) {
      const int m = n_fine >> level;  // fine steps per coarse step
      const double H = m * h;
      State s = init;
      const Stepper stepper;
      for (int c = 0; c < (1 << level); ++c) {
        Eigen::Array<double, L, Stepper::normals_per_source * S> xi;
        for (int j = 0; j < S; ++j) {
          Lanes dW = Lanes::Zero(), dZ = Lanes::Zero();
          for (int k = c * m; k < (c + 1) * m; ++k) {
            const Lanes w = std::sqrt(h) * xi_fine(k, j, 0);
            const Lanes zz = 0.5 * h * std::sqrt(h) * (xi_fine(k, j, 0) + xi_fine(k, j, 1) / std::sqrt(3.0));
            dZ += zz + dW * h;  // ∫ over the fine step of (W_s − W_{t_c}) ds
            dW += w;
          }
          const Lanes xi1 = dW / std::sqrt(H);
          const Lanes xi2 = std::sqrt(3.0) * (2.0 * dZ / (H * std::sqrt(H)) - xi1);
          if constexpr (Stepper::normals_per_source == 2) {
            xi.col(2 * j) = xi1;
            xi.col(2 * j + 1) = xi2;
          } else {
            xi.col(j) = xi1;
          }
        }
        stepper.step(sys, s, c * H, H, xi);
      }
      const Lanes e2 = (s.col(0) - ref.col(0)).square() + (s.col(1) - ref.col(1)).square();
      sq[static_cast<std::size_t>(level - k_min)] += e2.sum();
      for (int l = 0; l < L; ++l) out.log[static_cast<std::size_t>(level - k_min)].push_back(0.5 * std::log(e2(l)));
    }
  }
  for (auto& v : sq) out.rms.push_back(std::sqrt(v / (batches * L)));
  return out;
}

/// Least-squares slope of log(error) against log(H) (H halves per level), from the log errors.
double slope_in_log_H(const std::vector<double>& log_err) {
  const double n = static_cast<double>(log_err.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < log_err.size(); ++i) {
    const double x = -static_cast<double>(i) * std::log(2.0), y = log_err[i];
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

/// The order of the L² error: the slope of log sqrt(E e²) (one number per ladder).
double fitted_order(const LadderErrors& e) {
  std::vector<double> l;
  for (double v : e.rms) l.push_back(std::log(v));
  return slope_in_log_H(l);
}

/// The order of the typical error: the mean over paths of each path's slope of ½·log e²_i(H),
/// with its standard error from the spread of the independent paths' slopes.
vehs::Estimate path_order(const LadderErrors& e) {
  const std::size_t paths = e.log[0].size();
  double s = 0.0, s2 = 0.0;
  std::vector<double> l(e.log.size());
  for (std::size_t i = 0; i < paths; ++i) {
    for (std::size_t k = 0; k < l.size(); ++k) l[k] = e.log[k][i];
    const double p = slope_in_log_H(l);
    s += p, s2 += p * p;
  }
  const double n = static_cast<double>(paths), mean = s / n;
  return {mean, std::sqrt((s2 - n * mean * mean) / (n - 1.0) / n)};
}

/// Accepted ranges of the measured order. Over 17 seed shifts of the Brownian paths
/// (scripts/seed-study.sh 20 build/tests/test_sim "strong order on a ladder of steps*"): σ(x) and
/// hidden states 1.00–1.01 with sd 0.006–0.019 (EM, Eq. 30, BAOAB) and 1.68 / 1.85 with sd 0.017 /
/// 0.013 (Taylor 1.5): every bound ≥ 8 sd away.
/// With velocity noise σ(y) the L² order (fitted_order) scatters with sd 0.067–0.10 over seeds
/// (mean 0.50–0.54; Taylor 1.5: 1.53): 256 paths are too few for the heavy-tailed errors of that
/// noise, the lower bound was 2 sd away and the section failed in ≈ 4 % of runs (issue 11). That
/// section checks path_order instead: the mean over the 256 paths of each path's own slope of
/// log|e| (the same order for e_H = H^p·Z_H with Z_H converging in law), a mean of independent,
/// light-tailed slopes, so normal with the standard error the run computes (0.018 per run, the
/// seed-to-seed sd 0.018–0.019 agrees). Over 51 seed shifts (scripts/seed-study.sh 51
/// build/tests/test_sim "strong order on a ladder of steps*"): path order with σ(y) EM 0.563,
/// Eq. 30 0.555, BAOAB 0.521 (sd 0.018–0.019) and Taylor 1.5 1.489 (sd 0.016): the nearest bound
/// (BAOAB's 0.35) is 9.0 sd away, Taylor's 1.35 8.7 sd: false failure < 1e-15 per test case
/// (normal by the CLT over 256 paths). The L² order of the same runs broke the same bounds in 2
/// of the 51 (min 0.244 for EM, 1.198 for Taylor 1.5). Cost: none (the same paths). In these
/// runs the σ(x) and hidden-state orders were 1.00–1.01 (sd ≤ 0.017) and Taylor 1.5 1.67 / 1.85
/// (sd 0.015 / 0.013), as above.
/// Theory: Euler–Maruyama, Eq. 30 and BAOAB are strong
/// order 1 when σ depends on x only and 0.5 when it depends on y (the Milstein term);
/// Taylor 1.5 is at least 1.5 (measured higher here: its order-1.5 error terms have small
/// constants for these models, so the O(h²) terms dominate on this ladder).
template <class Stepper>
struct Expected {
  static constexpr double smooth_lo = 0.85, smooth_hi = 1.2, velocity_lo = 0.35, velocity_hi = 0.8;
};
template <>
struct Expected<Taylor15Stepper> {
  static constexpr double smooth_lo = 1.35, smooth_hi = 2.1, velocity_lo = 1.35, velocity_hi = 2.1;
};

struct Orders {
  double l2 = 0.0;          ///< fitted_order
  vehs::Estimate paths;     ///< path_order
};

template <class Stepper, class System>
Orders measure_order(const char* json, const char* label) {
  const auto cm = CompiledModel::from_model(model_of(json), "test");
  const auto err = strong_errors<Stepper, System>(cm, 0.8, -0.3, 4, 9, 14, 32);
  const Orders o{fitted_order(err), path_order(err)};
  std::printf("strong order %-16s %-28s %.3f, per path %.3f ± %.3f  (errors",
              vehs::enum_to_string(kSchemeNames, Stepper::scheme).c_str(), label, o.l2, o.paths.value,
              o.paths.stderr_);
  for (double e : err.rms) std::printf(" %.2e", e);
  std::printf(")\n");
  vehs_test::tally(std::string("order ") + label, o.l2);
  vehs_test::tally(std::string("path order ") + label, o.paths.value, o.paths.stderr_);
  return o;
}

const char* kDuffingMultiplicative =
    R"({"drift": {"x": -1.0, "x^3": -1.0, "y": -0.5}, "diffusion": {"1": 0.5, "x^2": 0.5}})";
const char* kVelocityNoise =
    R"({"drift": {"x": -1.0, "x^3": -1.0, "y": -0.5}, "diffusion": {"1": 0.5, "y^2": 1.5}})";
const char* kAllDynamicEffects =
    R"({"drift": {"x": -1.0, "x^3": -1.0, "y": -0.5}, "diffusion": {"1": 0.3, "x^2": 0.3},
        "effects": [{"name": "harmonic_forcing", "params": {"amplitude": 0.5, "omega": 2.0, "phase": 0.3}},
                    {"name": "electromechanical_coupling", "params": {"lambda": 1.5, "coupling": 0.8}},
                    {"name": "colored_noise", "params": {"tau": 0.5, "intensity": 0.4}}]})";

}  // namespace

TEMPLATE_TEST_CASE("strong order on a ladder of steps", "[convergence]", EulerMaruyamaStepper,
                   Rk4EulerStepper, BaoabStepper, Taylor15Stepper) {
  using Stepper = TestType;
  using E = Expected<Stepper>;
  SECTION("Duffing oscillator, multiplicative noise sigma(x)") {
    const double p = measure_order<Stepper, ModelSystem<L, false, false>>(kDuffingMultiplicative, "sigma(x)").l2;
    CHECK(p > E::smooth_lo);
    CHECK(p < E::smooth_hi);
  }
  SECTION("the same on the fast polynomial path") {
    const double p = measure_order<Stepper, PolynomialSystem<L, 2>>(kDuffingMultiplicative, "sigma(x), fast path").l2;
    CHECK(p > E::smooth_lo);
    CHECK(p < E::smooth_hi);
  }
  SECTION("velocity-dependent noise sigma(y): the Milstein term no longer vanishes") {
    const double p = measure_order<Stepper, ModelSystem<L, false, false>>(kVelocityNoise, "sigma(y)").paths.value;
    CHECK(p > E::velocity_lo);
    CHECK(p < E::velocity_hi);
  }
  SECTION("forcing, electromechanical coupling and coloured noise (hidden states, 2 noises)") {
    const double p = measure_order<Stepper, ModelSystem<L, true, true>>(kAllDynamicEffects, "hidden states").l2;
    CHECK(p > E::smooth_lo);
    CHECK(p < E::smooth_hi);
  }
}

namespace {

struct Bias {
  double value = 0.0;   ///< simulated − exact (relative to the exact value)
  double stderr_ = 0.0;
};

/// Long-run relative bias of E[Y²] of a scheme at step h on two exact cases:
///   Q = 0: E[Y²] = D/β (Gibbs density, any potential): bias = β E[Y²]/D − 1;
///   Q > 0: energy balance β E[Y²] − D − Q E[X²] = 0: bias = the residual / D.
/// β = 1, D = 0.5, U' = x + 0.1 x³ (Euler–Maruyama stays stable at h = 0.1); error bars from
/// the spread of 64 independent records of 20000 time units after a burn-in.
Bias long_run_bias(Scheme scheme, double h, bool multiplicative) {
  const double beta = 1.0, D = 0.5, Q = multiplicative ? 0.2 : 0.0;
  const auto m = model_of(multiplicative
                              ? R"({"drift": {"x": -1.0, "x^3": -0.1, "y": -1.0}, "diffusion": {"1": 1.0, "x^2": 0.4}})"
                              : R"({"drift": {"x": -1.0, "x^3": -0.1, "y": -1.0}, "diffusion": {"1": 1.0}})");
  SimulationOptions o;
  o.scheme = scheme;
  o.records = 64;
  o.dt = h;
  o.samples = static_cast<std::size_t>(std::llround(20000.0 / h));
  o.burn_in = 20.0;
  o.x0.uniform = false;
  o.x0.values.assign(64, 0.5);
  o.seed = vehs_test::seed(4242);
  StatisticsOptions so;
  const auto st = simulate_statistics(m, o, so);
  const auto& ex2 = st.record_means[2];
  const auto& ey2 = st.record_means[3];
  std::vector<vehs::Estimate> groups;
  std::vector<double> w;
  for (std::size_t r = 0; r < ex2.size(); ++r) {
    groups.push_back({(beta * ey2[r] - D - Q * ex2[r]) / D, 0.0});
    w.push_back(1.0);
  }
  const auto e = vehs::combine_independent(groups, w);
  return {e.value, e.stderr_};
}

}  // namespace

TEMPLATE_TEST_CASE("long-run weak bias of E[Y^2] against exact values", "[convergence]", EulerMaruyamaStepper,
                   Rk4EulerStepper, BaoabStepper, Taylor15Stepper) {
  const Scheme scheme = TestType::scheme;
  for (bool multiplicative : {false, true}) {
    const Bias coarse = long_run_bias(scheme, 0.1, multiplicative);
    const Bias fine = long_run_bias(scheme, 0.05, multiplicative);
    std::printf("weak bias %-16s %-28s h = 0.1: %+.5f ± %.5f   h = 0.05: %+.5f ± %.5f\n",
                vehs::enum_to_string(kSchemeNames, scheme).c_str(),
                multiplicative ? "Q > 0 (energy balance)" : "Q = 0 (E[Y^2] = D/beta)", coarse.value,
                coarse.stderr_, fine.value, fine.stderr_);
    const std::string tag = multiplicative ? " (Q > 0)" : " (Q = 0)";
    vehs_test::tally("coarse z" + tag, coarse.value / coarse.stderr_, coarse.value);
    vehs_test::tally("fine z" + tag, fine.value / fine.stderr_, fine.value);
    vehs_test::tally("ratio" + tag, coarse.value / fine.value);
    REQUIRE(coarse.stderr_ > 0);
    // The error bars come from 64 independent records (Student t, 63 dof). Measured (this seed):
    // EM 0.185 ± 0.0017 → 0.087 ± 0.0015 (Q = 0), 0.239 → 0.110 (Q > 0); Eq. 30 0.102 ± 0.0015 →
    // 0.050 ± 0.0014, 0.123 → 0.061; BAOAB −0.0037 ± 0.0014, −0.0053 ± 0.0017 at h = 0.1; Taylor 1.5
    // −0.0015 ± 0.0013, −0.0018 ± 0.0015.
    if (scheme == Scheme::EulerMaruyama || scheme == Scheme::Rk4Euler) {
      // first-order long-run bias: clearly resolved (≥ 60 SE), and halving h halves it: the ratio
      // (2.0–2.2 measured) has sd ≤ 0.065 by error propagation (independent estimates, an upper
      // bound for these shared-seed ones), so [1.6, 2.6] is ≥ 6.4 sd away: false failure < 1e-9
      CHECK(coarse.value > 10 * coarse.stderr_);
      const double ratio = coarse.value / fine.value;
      CHECK(ratio > 1.6);
      CHECK(ratio < 2.6);
    } else {
      // BAOAB and Taylor 1.5: below 1 % at h = 0.1 (Euler–Maruyama: ~20 %, Eq. 30: ~10 %). Four
      // checks per scheme: t_bound(4, 63) = 4.6 SE plus the allowance; BAOAB's real bias at h = 0.1
      // (−0.53 % ± 0.17 % with Q > 0) uses most of the 0.5 % allowance, leaving 4.4 SE (5e-6; with
      // the former 4 SE it left 3.8 SE, 7e-5)
      const double tb = vehs_test::t_bound(4, 63.0);
      CHECK(std::abs(coarse.value) < tb * coarse.stderr_ + 0.005);
      CHECK(std::abs(fine.value) < tb * fine.stderr_ + 0.002);
    }
  }
}

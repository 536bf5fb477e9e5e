// The verdict's calibration over data shapes (issue 13): the true model must be adequate on its
// own data for short and long records, few and many, scheme-consistent and continuous-time
// sampling. Small instances run in CI; the full matrix is a hidden bench tag:
//   VEHS_CAL_SEEDS=10 build/tests/test_diagnose "[.calibration_matrix]"
// (VEHS_CAL_SHAPE=text: only the shapes whose name contains it; VEHS_CAL_SEED0=k: seeds from k)
#include <catch2/catch.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <random>
#include <vector>

#include "diagnose_fixtures.hpp"
#include "vehs/identify/identify.hpp"

using namespace diag_test;

namespace {

struct Shape {
  std::string name;
  int records;
  std::size_t samples;
  double dt;
  int substeps;  ///< 1: the paper's rk4_euler at the recorded step; > 1: continuous-time (Taylor 1.5)
  double burn_in;
};

std::vector<Shape> shapes() {
  return {
      {"40 x 2000, dt 0.001, scheme, burn-in", 40, 2000, 0.001, 1, 50.0},
      {"40 x 2000, dt 0.001, scheme, no burn-in", 40, 2000, 0.001, 1, 0.0},
      {"40 x 2000, dt 0.01, continuous", 40, 2000, 0.01, 20, 50.0},
      {"100 x 500, dt 0.01, continuous", 100, 500, 0.01, 20, 50.0},
      {"8 x 20000, dt 0.01, continuous", 8, 20000, 0.01, 20, 50.0},
      {"4 x 50000, dt 0.02, continuous", 4, 50000, 0.02, 20, 50.0},
      {"32 x 6000, dt 0.05, continuous", 32, 6000, 0.05, 20, 50.0},
      {"200 x 1000, dt 0.001, scheme, burn-in", 200, 1000, 0.001, 1, 50.0},
  };
}

vehs::Dataset shape_data(const Shape& s, std::uint64_t seed) {
  vehs::sim::SimulationOptions o;
  o.dt = s.dt;
  o.substeps = s.substeps;
  o.scheme = s.substeps > 1 ? vehs::sim::Scheme::Taylor15 : vehs::sim::Scheme::Rk4Euler;
  o.records = s.records;
  o.samples = s.samples;
  o.burn_in = s.burn_in;
  o.record_y = false;
  o.seed = vehs_test::seed(seed);
  return vehs::sim::simulate(bistable(), o);
}

std::string failing(const vehs::diagnose::Result& r) {
  std::string s;
  for (const auto& c : r.components)
    if (c.test.available && c.test.p_value < r.threshold * 10)
      s += " " + c.name + " p=" + std::to_string(c.test.p_value);
  return s;
}

}  // namespace

TEST_CASE("calibration matrix: the true model on its own data, every shape (bench)", "[.calibration_matrix]") {
  const int seeds = std::getenv("VEHS_CAL_SEEDS") ? std::atoi(std::getenv("VEHS_CAL_SEEDS")) : 4;
  const char* only = std::getenv("VEHS_CAL_SHAPE");
  const int first = std::getenv("VEHS_CAL_SEED0") ? std::atoi(std::getenv("VEHS_CAL_SEED0")) : 1;
  for (const Shape& s : shapes()) {
    if (only && s.name.find(only) == std::string::npos) continue;
    int adequate = 0;
    for (int k = first; k < first + seeds; ++k) {
      const vehs::Dataset d = shape_data(s, 7000 + std::uint64_t(k));
      auto o = fast_options(std::uint64_t(k));
      o.suspects.enabled = false;
      o.fpk = false;
      const auto r = vehs::diagnose::diagnose(bistable(), d, o);
      adequate += r.adequate();
      std::printf("  %s seed %d: %s%s [lens %s, data sampling %s, sensor noise %.3g]\n", s.name.c_str(), k,
                  r.adequate() ? "adequate" : "INADEQUATE", failing(r).c_str(), r.lens.describe().c_str(),
                  vehs::enum_to_string(vehs::kSamplingVerdictNames, r.sampling.data_verdict).c_str(),
                  r.sampling.sensor_noise_sd);
      std::fflush(stdout);
    }
    std::printf("%s: adequate %d of %d\n", s.name.c_str(), adequate, seeds);
  }
}

// CI instance: the shapes that failed before the one-step map's bins counted their effective
// units (short records: 40 × 2 time units of the paper's scheme; many short records of a
// continuous process), three seeds each. The verdict's family-wise false-alarm level is 1 %;
// granting a calibration error of 2× (2 %), P(Bin(6, 0.98) < binomial_floor(6, 0.98)) ≤ 1e-4.
// Before the fix: 1 of 3 adequate on the first shape (one_step p = 2e-6, < 1e-6).
TEST_CASE("calibration matrix: short records, scheme-consistent and continuous-time", "[diagnose][calibration]") {
  int adequate = 0, runs = 0;
  for (const Shape& s : shapes()) {
    if (s.name != "40 x 2000, dt 0.001, scheme, burn-in" && s.name != "100 x 500, dt 0.01, continuous") continue;
    for (int k = 1; k <= 3; ++k) {
      const vehs::Dataset d = shape_data(s, 7100 + std::uint64_t(k));
      auto o = fast_options(std::uint64_t(k));
      o.suspects.enabled = false;
      o.fpk = false;
      const auto r = vehs::diagnose::diagnose(bistable(), d, o);
      UNSCOPED_INFO(s.name << " seed " << k << ": " << (r.adequate() ? "adequate" : "INADEQUATE") << failing(r));
      adequate += r.adequate();
      ++runs;
    }
  }
  CHECK(runs == 6);
  CHECK(adequate >= vehs_test::binomial_floor(6, 0.98));
}

// The sampling diagnosis behind the lens (identify's pilot with the model's terms, as
// diagnose's sampling pilot runs it) on the matrix's 200 × 1000 scheme data, seed 5: lag 2k
// alone read 5.9 % sensor noise there (a 3-sigma excess at lag 2k; ρ_k ≈ 0 contradicts it) and
// the true model failed every residual component. With lags k and 2k together the rule's
// standard error is 0.0036 on these 2·10⁵ rows: a false "noisy" needs 14 standard errors, and
// white noise of share ≈ 0.19 (s = 1e-6) is read at 40 of them — the checks cannot fail by
// chance (deterministic data; margins > 10 standard errors).
TEST_CASE("calibration matrix: many short scheme records are read as scheme-consistent, with sensor noise as noisy",
          "[diagnose][calibration][sampling]") {
  const Shape s = shapes().back();
  REQUIRE(s.name == "200 x 1000, dt 0.001, scheme, burn-in");
  vehs::Dataset d = shape_data(s, 7005);
  vehs::identify::Options o;
  o.drift_library = {vehs::Term::monomial(1, 0), vehs::Term::monomial(3, 0), vehs::Term::monomial(0, 1)};
  o.diffusion_library = {vehs::Term::monomial(0, 0), vehs::Term::monomial(2, 0)};
  o.sparsity = vehs::identify::Sparsity::None;
  o.folds = 1;
  auto read = [&](const vehs::Dataset& data) { return *vehs::identify::identify(data, o).model.fit; };
  const vehs::FitInfo clean = read(d);
  INFO("rho_k " << clean.sampling.rho_k << " rho_2k " << clean.sampling.rho_2k << " rho_3k " << clean.sampling.rho_3k);
  CHECK(clean.sampling.verdict == vehs::SamplingVerdict::SchemeConsistent);
  CHECK(clean.sampling.noise_share < 0.02);
  std::mt19937_64 rng(vehs_test::seed(5));
  std::normal_distribution<double> noise(0.0, 1e-6);
  for (double& x : d.x) x += noise(rng);
  const vehs::FitInfo noisy = read(d);
  CHECK(noisy.sampling.verdict == vehs::SamplingVerdict::Noisy);
  CHECK(noisy.sampling.noise_share > 0.1);
}

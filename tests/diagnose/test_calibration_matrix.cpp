// The verdict's calibration over data shapes (issue 13): the true model must be adequate on its
// own data for short and long records, few and many, scheme-consistent and continuous-time
// sampling. Small instances run in CI; the full matrix is a hidden bench tag:
//   VEHS_CAL_SEEDS=10 build/tests/test_diagnose "[.calibration_matrix]"
// (VEHS_CAL_SHAPE=text: only the shapes whose name contains it; VEHS_CAL_SEED0=k: seeds from k)
#include <catch2/catch.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "diagnose_fixtures.hpp"

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

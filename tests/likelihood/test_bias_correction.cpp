// The simulation-based bias correction of the likelihood estimate
// (detail/bias_correction.hpp): its simulated data copy the data's design, and where the filter
// is exact (a linear model with constant diffusion: the Gaussian filter is the Kalman filter)
// its shift is pure Monte Carlo noise of known size, N(0, covariance/B), while the covariance is
// inflated by exactly 1 + 1/B.
#include <catch2/catch.hpp>

#include <cmath>

#include "likelihood_fixtures.hpp"
#include "vehs/likelihood/detail/bias_correction.hpp"
#include "vehs/likelihood/refine.hpp"

using namespace vehs;
using namespace vehs_lik_test;

TEST_CASE("bias correction: simulated data sets copy the records, lengths, sampling and input",
          "[likelihood][bias_correction]") {
  const Model driven = model(R"({"drift": {"x": -1.0, "y": -0.2, "u": 1.0}, "diffusion": {"1": 0.01}})");
  std::vector<double> u(300);
  for (std::size_t i = 0; i < u.size(); ++i) u[i] = std::sin(0.3 * double(i));
  Dataset d = simulate(driven, 0.5, 2, 150.0, 7, 0.01, 20, &u);
  // make the second record shorter than the first
  d.records[1].size = 200;
  d.x.resize(d.records[1].offset + 200);
  d.u.resize(d.records[1].offset + 200);
  const likelihood::ObservedModel m{driven, 0.01, {}};
  const Dataset s = likelihood::detail::simulate_like(m, d, 20, 3);
  REQUIRE(s.records.size() == 2);
  CHECK(s.records[0].size == 300);
  CHECK(s.records[1].size == 200);
  CHECK(s.x.size() == 500);
  CHECK(s.records[1].dt == Approx(0.5));
  REQUIRE(s.u.size() == 500);
  for (std::size_t r = 0; r < 2; ++r) {
    CHECK(s.u_of(s.records[r])[5] == d.u_of(d.records[r])[5]);
    // the first sample is the data's plus the sensor noise (0.01): within 6 sd (p < 2e-9)
    CHECK(std::abs(s.x_of(s.records[r])[0] - d.x_of(d.records[r])[0]) < 0.06);
  }
  likelihood::RefineOptions o;
  o.bias_correction_datasets = -1;
  std::string why;
  CHECK_FALSE(o.IsValid(&why));
  CHECK(why.find("bias_correction_datasets") != std::string::npos);
  o.bias_correction_datasets = 4;
  o.per_record_phase = true;
  CHECK_FALSE(o.IsValid(&why));
  CHECK(why.find("per_record_phase") != std::string::npos);
}

// False-failure probability per run ≤ 1e-4: four parameters, each shift outside
// z_bound(4) / √B standard errors with probability ≤ 2.5e-5 when the filter is exact (the
// shift is −C·b̂, b̂ the mean of B scores with covariance I each, so shift/SE ~ N(0, 1/B)).
TEST_CASE("bias correction where the filter is exact: a shift of Monte Carlo size, covariance x (1 + 1/B)",
          "[likelihood][bias_correction]") {
  const Model linear = model(R"({"drift": {"x": -1.0, "y": -0.2}, "diffusion": {"1": 0.04}})");
  const Dataset d = simulate(linear, 0.5, 4, 1000.0, 11, 0.02);
  likelihood::RefineOptions o;
  const likelihood::Result plain = likelihood::refine({linear, 0.02, {}}, d, o);
  o.bias_correction_datasets = 8;
  const likelihood::Result corrected = likelihood::refine({linear, 0.02, {}}, d, o);
  INFO(corrected.summary.FullReport());
  REQUIRE(corrected.parameters.size() == plain.parameters.size());
  CHECK(corrected.summary.bias_correction_datasets == 8);
  for (std::size_t i = 0; i < plain.parameters.size(); ++i) {
    INFO(plain.parameters[i].name << ": " << plain.values[i] << " -> " << corrected.values[i] << " (SE "
                                  << plain.stderrs[i] << ")");
    if (plain.parameters[i].log_scale) {  // covariance mapped at the corrected value
      CHECK(corrected.stderrs[i] / corrected.values[i] ==
            Approx(plain.stderrs[i] / plain.values[i] * std::sqrt(1.0 + 1.0 / 8)).epsilon(1e-9));
    } else {
      CHECK(corrected.stderrs[i] == Approx(plain.stderrs[i] * std::sqrt(1.0 + 1.0 / 8)).epsilon(1e-9));
    }
    const double shift = std::abs(corrected.values[i] - plain.values[i]) / plain.stderrs[i];
    CHECK(shift <= z_bound(4) / std::sqrt(8.0));
  }
}

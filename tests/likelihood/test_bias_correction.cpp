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

// An input the filter interpolates is applied the same way in the simulated data sets. Data: a
// linear oscillator driven by an input linearly interpolated between its samples (built here by
// hand and simulated at Δt/40 with the input held at the midpoints of the fine steps, then
// decimated), fitted with input "linear": the filter is exact, so the correction's shift is
// Monte Carlo noise, N(0, 1/B) in SE units. Simulated data sets that held the input over each
// interval instead (the correction before this test) moved drift[u] by 108 SE, drift[x] by 104.
// False-failure probability per run ≤ 1e-4: five parameters, each shift outside z_bound(5)/√B
// with probability ≤ 2e-5.
TEST_CASE("bias correction with an interpolated input: simulated data driven as the filter drives the model",
          "[likelihood][bias_correction]") {
  const Model driven = model(R"({"drift": {"x": -1.0, "y": -0.2, "u": 1.0}, "diffusion": {"1": 0.01}})");
  const double dt = 0.5;
  const int fine = 40, n = 1000;
  std::vector<double> u(n), u_fine(std::size_t((n - 1) * fine));
  for (int k = 0; k < n; ++k) u[std::size_t(k)] = std::sin(0.9 * k) + 0.5 * std::sin(2.3 * k);
  for (std::size_t j = 0; j < u_fine.size(); ++j) {
    const double s = (double(j % fine) + 0.5) / fine;
    const std::size_t k = j / fine;
    u_fine[j] = (1 - s) * u[k] + s * u[k + 1];
  }
  const Dataset f = simulate(driven, dt / fine, 3, double((n - 1) * fine + 1) * dt / fine, 13, 0.01, 1, &u_fine);
  Dataset d;
  for (const Record& r : f.records) {
    Record rec = r;
    rec.offset = d.x.size();
    rec.dt = dt;
    rec.size = std::size_t(n);
    for (int k = 0; k < n; ++k) {
      d.x.push_back(f.x_of(r)[std::size_t(k * fine)]);
      d.u.push_back(u[std::size_t(k)]);
    }
    d.records.push_back(rec);
  }
  likelihood::RefineOptions o;
  o.filter.input = InputInterpolation::Linear;
  const likelihood::Result plain = likelihood::refine({driven, 0.01, {}}, d, o);
  o.bias_correction_datasets = 8;
  o.bias_correction_seed = 21;
  const likelihood::Result corrected = likelihood::refine({driven, 0.01, {}}, d, o);
  INFO(corrected.summary.FullReport());
  REQUIRE(corrected.parameters.size() == 5);
  CHECK(corrected.summary.bias_correction_seed == 21);
  for (std::size_t i = 0; i < plain.parameters.size(); ++i) {
    INFO(plain.parameters[i].name << ": " << plain.values[i] << " -> " << corrected.values[i] << " (SE "
                                  << plain.stderrs[i] << ")");
    CHECK(std::abs(corrected.values[i] - plain.values[i]) / plain.stderrs[i] <= z_bound(5) / std::sqrt(8.0));
  }
}

TEST_CASE("bias correction auto: only for fits with resolved sensor noise - one that cannot be done is skipped with the reason",
          "[likelihood][bias_correction]") {
  const Model linear = model(R"({"drift": {"x": -1.0, "y": -0.2}, "diffusion": {"1": 0.04}})");
  const Dataset d = simulate(linear, 0.5, 2, 500.0, 17, 0.02);
  likelihood::RefineOptions o;
  o.bias_correction_datasets = 8;
  o.bias_correction_auto = true;
  o.per_record_phase = true;  // (auto: valid, the correction is simply not done)
  std::string why;
  CHECK(o.IsValid(&why));
  o.per_record_phase = false;
  o.estimate_measurement_noise = false;
  const likelihood::Result no_noise = likelihood::refine({linear, 0.0, {}}, d, o);
  CHECK(no_noise.summary.bias_correction_datasets == 0);
  CHECK(no_noise.summary.bias_correction_skipped.empty());
  // sensor noise fitted but not resolved (noise-free records: an estimate at the boundary, below
  // 2 SE): no sensor to correct for (an outside tester: B = 8 ran on every noise-free loop fit)
  o.estimate_measurement_noise = true;
  const likelihood::Result unresolved = likelihood::refine({linear, 0.0, {}}, simulate(linear, 0.5, 2, 500.0, 17, 0.0), o);
  INFO(unresolved.summary.FullReport());
  REQUIRE(unresolved.find("measurement_sd") >= 0);
  CHECK(unresolved.stderrs[std::size_t(unresolved.find("measurement_sd"))] >
        0.5 * unresolved.values[std::size_t(unresolved.find("measurement_sd"))]);
  CHECK(unresolved.summary.bias_correction_datasets == 0);
  CHECK(unresolved.summary.bias_correction_skipped.empty());
  // a fit the simulator refuses (x^3 held at +0.05: a potential that does not confine; the
  // filter is fine on these data, |x| < 1): uncorrected, and the reason kept
  o.estimate_measurement_noise = true;
  Model open = linear;
  open.drift.push_back({Term::parse("x^3"), 0.05});
  canonicalize(open.drift, "test");
  o.fixed = {"drift[x^3]"};
  const likelihood::Result skipped = likelihood::refine({open, 0.02, {}}, d, o);
  INFO(skipped.summary.FullReport());
  CHECK(skipped.summary.bias_correction_datasets == 0);
  CHECK(skipped.summary.bias_correction_skipped.find("cannot simulate the fitted model") != std::string::npos);
  o.bias_correction_auto = false;
  CHECK_THROWS_WITH(likelihood::refine({open, 0.02, {}}, d, o), Catch::Contains("cannot simulate the fitted model"));
}

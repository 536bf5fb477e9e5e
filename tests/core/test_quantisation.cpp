// The grid of quantised records (vehs/core/quantisation.hpp): the step of integer counts and of
// values printed with fixed decimals, per-record origins, nothing on float data, and the stride
// from which increments spread over a step.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "oscillator_records.hpp"
#include "vehs/core/quantisation.hpp"

using core_test::oscillator;

TEST_CASE("float records are not quantised", "[core][quantisation][asan]") {
  const vehs::Quantisation q = vehs::find_quantisation(oscillator(20000, 3, 2));
  CHECK_FALSE(q.quantised());
  CHECK(q.dither_stride == 1);
}

TEST_CASE("integer counts: step 1, from any per-record origin", "[core][quantisation][asan]") {
  vehs::Dataset d = oscillator(20000, 4, 3);
  for (double& x : d.x) x = std::round(200.0 * x);
  const vehs::Quantisation q = vehs::find_quantisation(d);
  CHECK(q.step == Approx(1.0).epsilon(1e-12));
  CHECK(q.noise_variance() == Approx(1.0 / 12.0).epsilon(1e-12));
  // detrend subtracts a different non-integer mean from each record: the grid stays
  for (std::size_t r = 0; r < d.records.size(); ++r)
    for (std::size_t i = 0; i < d.records[r].size; ++i) d.x[d.records[r].offset + i] -= 0.3183 * double(r + 1);
  CHECK(vehs::find_quantisation(d).step == Approx(1.0).epsilon(1e-9));
  d.x[d.records[1].offset + 17] += 0.25;  // one value off the grid
  CHECK_FALSE(vehs::find_quantisation(d).quantised());
}

TEST_CASE("values printed with 3 decimals and read back: step 0.001", "[core][quantisation][asan]") {
  vehs::Dataset d = oscillator(20000, 5, 2);
  char buf[64];
  for (double& x : d.x) {
    std::snprintf(buf, sizeof buf, "%.3f", x);
    x = std::strtod(buf, nullptr);
  }
  CHECK(vehs::find_quantisation(d).step == Approx(1e-3).epsilon(1e-9));
}

TEST_CASE("the dither stride: the first doubling whose increments spread over a step",
          "[core][quantisation][asan]") {
  // a ramp of slope s per sample in counts: sd of x_{i+k} − x_i is k·s, so the stride is the
  // first power of 2 with k·s ≥ 1 (up to the rounding of the ramp itself)
  for (double slope : {0.8, 0.3, 0.07}) {
    vehs::Dataset d;
    std::vector<double> x(4000);
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::round(slope * double(i) + 100.0 * std::sin(0.001 * double(i)));
    d.x = vehs::Column(std::move(x));
    vehs::Record r;
    r.dt = 1.0;
    r.size = 4000;
    d.records.push_back(r);
    const vehs::Quantisation q = vehs::find_quantisation(d);
    INFO("slope " << slope);
    REQUIRE(q.quantised());
    const int k = q.dither_stride;
    CHECK(k >= 1);
    CHECK(double(k) * (slope + 0.1) >= 1.0);  // spread reached (the sine adds ≤ 0.1 per sample)
    if (k > 1) CHECK(double(k / 2) * slope < 1.0 + 0.2);  // and not before
  }
}

TEST_CASE("the step is written without the round-off of the spacing of parsed values", "[core][quantisation][asan]") {
  vehs::Dataset d = oscillator(5000, 6, 1);
  char buf[64];
  for (double& x : d.x) {
    std::snprintf(buf, sizeof buf, "%.3f", 3.7 + x);  // an offset: spacings like 3.701 − 3.700
    x = std::strtod(buf, nullptr);
  }
  CHECK(vehs::find_quantisation(d).step == 0.001);
}

TEST_CASE("empty and one-sample records are skipped", "[core][quantisation][asan]") {
  vehs::Dataset d = oscillator(4000, 8, 2);
  for (double& x : d.x) x = std::round(100.0 * x);
  vehs::Record empty = d.records[1];
  empty.offset = d.x.size();
  empty.size = 0;
  d.records.push_back(empty);
  const vehs::Quantisation q = vehs::find_quantisation(d);
  CHECK(q.step == 1.0);
}

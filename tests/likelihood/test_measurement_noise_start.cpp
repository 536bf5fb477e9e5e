// The start of the measurement noise's sd (detail/measurement_noise_start.hpp) on the
// colored_noise case of issue 13 (bistable Duffing, OU excitation τ 0.6, Taylor 1.5 at 20
// substeps per sample, Δt 0.05): the case where refine, started at a fixed 1 % of std(x) on
// noise-free records, stopped unconverged at τ 0.018.
#include <catch2/catch.hpp>

#include <cmath>

#include "diagnose/score_fixtures.hpp"
#include "vehs/likelihood/detail/data_scales.hpp"
#include "vehs/likelihood/detail/measurement_noise_start.hpp"
#include "vehs/likelihood/refine.hpp"

using namespace vehs;

namespace {

score_test::HiddenCase colored_case(int records, double sensor_noise_share) {
  for (auto c : score_test::hidden_cases())
    if (c.name == "colored_noise") {
      c.records = records;
      c.sensor_noise_share = sensor_noise_share;
      return c;
    }
  throw std::logic_error("no colored_noise case");
}

Model moment_fit(const score_test::HiddenCase& c, const Dataset& d) {
  identify::Options io = score_test::baseline_options_for(c);
  Effect e;
  e.id = EffectId::ColoredNoise;
  io.effects = {e};
  return identify::identify(d, io).model;
}

}  // namespace

// Deterministic (fixed data): the log-likelihood differences between the grid's points are
// thousands of units on these 32 000 samples, far beyond the data's draw.
TEST_CASE("the measurement sd starts at the grid point of highest likelihood: below 0.1 % of "
          "std(x) on noise-free records, 1-3 % with 2 % sensor noise", "[likelihood][refine]") {
  for (double share : {0.0, 0.02}) {
    const score_test::HiddenCase c = colored_case(8, share);
    const Dataset d = score_test::hidden_data(c, 100);
    const likelihood::ObservedModel start{moment_fit(c, d), 0.0, {}};
    const double sd = std::sqrt(likelihood::detail::x_variance(d));
    const double s = likelihood::detail::measurement_sd_start(start, d, {}, false);
    INFO("sensor noise " << share << " of std(x): start " << s / sd << " of std(x)");
    if (share == 0.0) CHECK(s <= 0.001 * sd * 1.0001);
    else CHECK((s >= 0.01 * sd * 0.9999 && s <= 0.03 * sd * 1.0001));
  }
}

// Seed 100 (k = 0) of the study at 32 records, where the fixed 1 % start ended at τ 0.018
// (log L 1900 below the maximum, "NOT converged", 47 s). The estimate is a fixed number; the
// bound 4 SE (normal tail 6e-5) is what any other seed would pass with probability ≥ 1 − 1e-4.
TEST_CASE("refine from the moment fit on noise-free colored_noise records converges to the "
          "truth's neighbourhood", "[likelihood][refine][slow]") {
  const score_test::HiddenCase c = colored_case(32, 0.0);
  const Dataset d = score_test::hidden_data(c, 100);
  const likelihood::Result r = likelihood::refine({moment_fit(c, d), 0.0, {}}, d);
  INFO(r.summary.BriefReport());
  CHECK(r.summary.converged);
  const int t = r.find("colored_noise.tau"), b = r.find("drift[y]");
  REQUIRE(t >= 0);
  REQUIRE(b >= 0);
  CHECK(std::abs(r.values[std::size_t(t)] - 0.6) <= 4.0 * r.stderrs[std::size_t(t)]);
  CHECK(std::abs(r.values[std::size_t(b)] + 0.1) <= 4.0 * r.stderrs[std::size_t(b)]);
}

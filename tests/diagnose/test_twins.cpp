// The twins' simulator (src/diagnose/twins.cpp): its memory guard, and the input it carries.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "../../src/diagnose/twins.hpp"
#include "diagnose_fixtures.hpp"
#include "vehs/core/error.hpp"

using namespace vehs;

TEST_CASE("twins: an interpolated drive too large for the memory limit is refused before it is refined",
          "[diagnose][twins][errors]") {
  // one driven record of 10^5 samples, its input applied linearly (the model fit's estimator.input)
  // on 2000 steps per interval: the refined drive alone would be 2·10^8 values (1.6 GB), the twin
  // and its drive copy as much again; the simulator's limit, here 1 GB, refuses all of it at once
  Model m = diag_test::model_of(R"({"drift": {"x": -1.0, "y": -0.2, "u": 1.0}, "diffusion": {"1": 0.01}})");
  m.fit = FitInfo{};
  m.fit->input = InputInterpolation::Linear;
  const std::size_t n = 100000;
  Dataset d;
  Record r;
  r.source = "driven.csv";
  r.dt = 0.1;
  r.size = n;
  d.records.push_back(r);
  d.x.assign(n, 0.0);
  d.u.resize(n);
  for (std::size_t k = 0; k < n; ++k) d.u[k] = std::sin(0.01 * static_cast<double>(k));
  diagnose::detail::TwinSettings ts;
  ts.input = InputInterpolation::Linear;
  ts.substeps = 2000;
  ts.memory_limit = 1e9;
  diagnose::detail::TwinSimulator twins(m, d, ts);
  Dataset out;
  std::string what;
  try {
    twins.simulate(0, out);
  } catch (const Error& e) {
    what = e.what();
  }
  INFO(what);
  CHECK(what.find("simulating the model's twins of the data failed: simulation: the records would need 4.79995 GB") !=
        std::string::npos);
  CHECK(what.find("GB of memory (limit 1 GB)") != std::string::npos);
  CHECK(what.find('\n') == std::string::npos);
  // 4.8 GB counts the refined drive (2·10^8 values) besides the twin's x and u: the check came
  // before the drive was built (the simulator's own, after it, would say 3.2); refining it would
  // take about a second, the refusal takes microseconds

  // within the limit the same twins are simulated (a shorter record)
  d.records[0].size = 1000;
  d.x.resize(1000);
  d.u.resize(1000);
  diagnose::detail::TwinSimulator small(m, d, ts);
  small.simulate(0, out);
  CHECK(out.x.size() == 1000);
  // the twins carry the input that drove them: refits of the twins (the parameter-uncertainty
  // draws) need it — with an interpolated input they had none, and an outside tester's driven rig
  // lost its parameter uncertainty with "the data have no drive column u"
  REQUIRE(out.u.size() == 1000);
  CHECK(out.u[500] == d.u[500]);
}

TEST_CASE("twins: data in physical units x1e12 are simulated (a divergence bound in the data's units)",
          "[diagnose][twins]") {
  // the simulator's default bound, 1e8, stopped every twin of data x1e12 at its first step and no
  // key raised it; the bound is now a multiple of the data's own extent
  const Model m = diag_test::model_of(R"({"drift": {"x": -1.0, "x^3": -1.0, "y": -0.1}, "diffusion": {"1": 0.2}})");
  const Model scaled_model =
      diag_test::model_of(R"({"drift": {"x": -1.0, "x^3": -1e-24, "y": -0.1}, "diffusion": {"1": 2e23}})");
  diag_test::DataSpec spec;
  spec.records = 2;
  spec.samples = 2000;
  const Dataset d = diag_test::simulate(m, spec);
  Dataset scaled = d;
  for (auto& v : scaled.x) v *= 1e12;
  const double bound = diagnose::detail::twin_divergence_bound(d);
  CHECK(bound > 1e8);  // |dx/dt| of the data exceeds 1
  CHECK(diagnose::detail::twin_divergence_bound(scaled) == Approx(1e12 * bound));
  diagnose::detail::TwinSimulator twins(scaled_model, scaled, diagnose::detail::TwinSettings{});
  Dataset out;
  REQUIRE_NOTHROW(twins.simulate(0, out));
  REQUIRE(out.x.size() == scaled.x.size());
  double most = 0.0;
  for (double v : out.x) most = std::max(most, std::abs(v));
  CHECK(most > 1e11);
  CHECK(most < 1e14);
}

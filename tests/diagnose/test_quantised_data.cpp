// Quantised records (vehs/core/quantisation.hpp) diagnosed with their true model's fit. A second
// outside tester's kind of data: a bistable written as 12-bit counts at 20 kHz. The held-out
// suspects' moment refits read the staircase rounding as a hidden state (electromechanical_
// coupling 1772 nats, z 45, suspects p 3e-20: the true model judged inadequate); their evidence
// now stands aside there and the twins are rounded to the data's grid.
#include <catch2/catch.hpp>

#include <cmath>

#include "diagnose_fixtures.hpp"
#include "identify/identify_fixtures.hpp"

using namespace diag_test;

// False failure ≤ 1e-4: eleven components, each below p = 1e-6 with probability 1e-6 under the
// model (the components are calibrated; the verdict itself is a family-wise 1 % test, too
// loose to assert on one seed).
TEST_CASE("integer counts at a fast rate: the true model's fit is not refuted and the held-out "
          "suspects stand aside", "[diagnose][quantised]") {
  const vehs::Model truth = vehs::model_from_json(nlohmann::json::parse(R"({
    "drift": {"x": 986.96, "x^3": -0.0941, "y": -6.2832}, "diffusion": {"1": 3.25e7}})"), "bistable in counts");
  vehs::Dataset d = vehs_test::simulate(truth, 5e-5, 4, 4, 30000, 5101, 0.0, vehs::sim::Scheme::Taylor15);
  for (double& x : d.x) x = std::round(x);
  vehs::identify::Options io;
  io.drift_library = {vehs::Term::parse("x"), vehs::Term::parse("x^3"), vehs::Term::parse("y")};
  io.diffusion_library = {vehs::Term::parse("1")};
  io.sparsity = vehs::identify::Sparsity::None;
  const vehs::Model fit = vehs::identify::identify(d, io).model;
  REQUIRE(fit.fit);
  REQUIRE(fit.fit->sampling.quantisation_step == Approx(1.0));
  const vehs::diagnose::Result r = vehs::diagnose::diagnose(fit, d, fast_options(7));
  bool suspects_aside = false;
  for (const auto& c : r.components) {
    INFO(c.name << " p " << c.test.p_value << " " << c.test.note);
    if (c.name == "suspects") suspects_aside = !c.test.available && c.test.note.find("grid") != std::string::npos;
    if (c.test.available) CHECK(c.test.p_value > 1e-6);
  }
  CHECK(suspects_aside);
  // the held-out ranking is kept for reference, marked as not a test and never claimed
  CHECK(r.suspects.set_aside.find("grid") != std::string::npos);
  for (const auto& sp : r.suspects.ranked) CHECK_FALSE(sp.significant);
}

// False failure ≤ 1e-4: as above (each available component below p = 1e-6 with probability 1e-6
// under the model); the control at stride 1 failed 4 of 4 of an outside tester's files at
// p 1e-31 … 1e-64 and fails here at p 7e-9 (this fixed seed; asserted below 1e-6).
TEST_CASE("counts at 20 kHz whose rounding is white: the lens reads them at a stride where the "
          "rounding is at most half of the whitening variance", "[diagnose][quantised][rounding_stride]") {
  // a second outside tester's Duffing (10 Hz, β 6.28, k 1000, σ 223) in 12-bit counts of ±2.5 at
  // 20 kHz: the signal moves several counts a sample, the rounding is white at stride 1 and 99 %
  // of â's variance there; the one-step residuals live on a lattice of step √2 whose occupation in
  // a (x, v̂) bin depends on the path below one count — the true model was judged inadequate.
  const double lsb = 5.0 / 4096.0, w = 2.0 * M_PI * 10.0;
  const vehs::Model truth = vehs::model_from_json(
      nlohmann::json{{"drift", {{"x", -w * w}, {"x^3", -1000.0 * lsb * lsb}, {"y", -6.28}}},
                     {"diffusion", {{"1", 223.0 * 223.0 / (lsb * lsb)}}}},
      "Duffing in 12-bit counts");
  vehs::Dataset d = vehs_test::simulate(truth, 5e-5, 4, 4, 60000, 5103, 0.0, vehs::sim::Scheme::Taylor15);
  for (double& x : d.x) x = std::round(x);
  const vehs::diagnose::Result r = vehs::diagnose::diagnose(truth, d, fast_options(9));
  INFO("lens stride " << r.lens.stride);
  CHECK(r.lens.stride >= 4);
  for (const auto& c : r.components) {
    INFO(c.name << " p " << c.test.p_value << " " << c.test.note);
    if (c.test.available) CHECK(c.test.p_value > 1e-6);
  }
  vehs::diagnose::Options one = fast_options(9);
  one.stride = 1;  // the former lens
  const vehs::diagnose::Result r1 = vehs::diagnose::diagnose(truth, d, one);
  for (const auto& c : r1.components)
    if (c.name == "one_step") CHECK(c.test.p_value < 1e-6);
}

// What diagnose needs from a fit (estimator, stride, sampling interval and diagnosis, sensor
// noise) is a typed part of the model (Model::fit): a model identified in C++, the same model
// written to a model file and read back, and the same model built by hand in C++ give identical
// diagnoses; without a stated fit the lens comes from the data instead.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include "diagnose_fixtures.hpp"
#include "vehs/io/model_file.hpp"

using namespace diag_test;
using vehs::diagnose::Result;

namespace {

void require_identical(const Result& a, const Result& b) {
  CHECK(a.verdict == b.verdict);
  CHECK(a.score == b.score);
  REQUIRE(a.components.size() == b.components.size());
  for (std::size_t k = 0; k < a.components.size(); ++k) {
    INFO(a.components[k].name);
    CHECK(a.components[k].name == b.components[k].name);
    CHECK(a.components[k].test.available == b.components[k].test.available);
    CHECK(a.components[k].test.statistic == b.components[k].test.statistic);
    CHECK(a.components[k].test.p_value == b.components[k].test.p_value);
  }
  CHECK(a.lens.describe() == b.lens.describe());
  CHECK(a.sampling.model_estimator == b.sampling.model_estimator);
  CHECK(a.sampling.model_verdict == b.sampling.model_verdict);
  CHECK(a.sampling.model_dt == b.sampling.model_dt);
  CHECK(a.parameter_draws == b.parameter_draws);
}

}  // namespace

TEST_CASE("a model identified in C++, read from its file, or built by hand diagnoses identically",
          "[diagnose][fit_info]") {
  // a sensor sampling a continuous process: identify chooses central kinematics (uli)
  const DataSpec s = sensor_records(31);
  const vehs::Dataset d = simulate(bistable(), s);
  const vehs::Model identified = fit(d, {"x", "x^3", "y"}, {"1", "x^2"});
  REQUIRE(identified.fit);
  CHECK(identified.fit->estimator == vehs::Estimator::Uli);
  CHECK(identified.fit->sampling.dt == s.dt);

  const std::string path = (std::filesystem::temp_directory_path() / "vehs_fit_info_model.json").string();
  vehs::write_model_file(path, identified);
  const vehs::Model from_file = vehs::load_model_file(path);
  REQUIRE(from_file.fit);
  CHECK(from_file.fit->estimator == identified.fit->estimator);
  CHECK(from_file.fit->stride == identified.fit->stride);
  CHECK(from_file.fit->sampling.verdict == identified.fit->sampling.verdict);

  // by hand: the same coefficients, standard errors and fit, no JSON involved
  vehs::Model by_hand;
  by_hand.drift = identified.drift;
  by_hand.diffusion = identified.diffusion;
  by_hand.drift_stderr = identified.drift_stderr;
  by_hand.diffusion_stderr = identified.diffusion_stderr;
  vehs::FitInfo fit;
  fit.estimator = vehs::Estimator::Uli;
  fit.stride = identified.fit->stride;
  fit.sampling.dt = s.dt;
  fit.sampling.verdict = identified.fit->sampling.verdict;
  by_hand.fit = fit;

  auto o = fast_options(5);
  o.fpk = false;
  o.suspects.enabled = false;
  o.parameter_draws = 2;
  o.parameter_fit_samples = 2e4;
  const Result a = vehs::diagnose::diagnose(identified, d, o);
  const Result b = vehs::diagnose::diagnose(from_file, d, o);
  const Result c = vehs::diagnose::diagnose(by_hand, d, o);
  CHECK(a.sampling.model_estimator == vehs::Estimator::Uli);
  CHECK(a.parameter_draws == 2);  // the model reports standard errors: its uncertainty is used
  require_identical(a, b);
  require_identical(a, c);

  // a model that states no fit: nothing to compare the data's sampling with
  vehs::Model unfitted = by_hand;
  unfitted.fit.reset();
  const Result u = vehs::diagnose::diagnose(unfitted, d, o);
  CHECK(u.sampling.model_estimator == vehs::Estimator::Auto);
  CHECK(u.sampling.model_dt == 0.0);
}

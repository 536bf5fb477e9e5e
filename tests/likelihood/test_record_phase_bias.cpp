// The free phases' bias of the shared forcing amplitude (detail/record_phase_bias.hpp): the
// correction's arithmetic on a result whose phase variances are given, and refine()'s refusal of
// per-record phases it would ignore. (The bias itself, measured against fits with the true phases
// held, is in the header.)
#include <catch2/catch.hpp>

#include <string>

#include "likelihood_fixtures.hpp"
#include "vehs/core/error.hpp"
#include "vehs/likelihood/detail/record_phase_bias.hpp"

using namespace vehs;

namespace {

/// A result with the amplitude A (variance va) and R phases of variances var[r].
likelihood::Result phases_result(double A, double va, const std::vector<double>& var) {
  likelihood::Result r;
  Effect e;
  e.id = EffectId::HarmonicForcing;
  e.params = {{"amplitude", A}, {"omega", 0.8}, {"phase", 0.0}};
  e.stderr_ = {{"amplitude", std::sqrt(va)}};
  r.model.model.effects.push_back(e);
  const std::size_t n = 1 + var.size();
  r.parameters.resize(n);
  r.parameters[0].name = "harmonic_forcing.amplitude";
  r.parameters[0].kind = likelihood::ParameterKind::Effect;
  r.covariance = Eigen::MatrixXd::Zero(Eigen::Index(n), Eigen::Index(n));
  r.covariance(0, 0) = va;
  r.values = {A};
  r.stderrs = {std::sqrt(va)};
  for (std::size_t i = 0; i < var.size(); ++i) {
    r.parameters[i + 1].name = "phase[" + std::to_string(i) + "]";
    r.parameters[i + 1].kind = likelihood::ParameterKind::RecordPhase;
    r.covariance(Eigen::Index(i + 1), Eigen::Index(i + 1)) = var[i];
    r.covariance(0, Eigen::Index(i + 1)) = r.covariance(Eigen::Index(i + 1), 0) = 1e-6;
    r.values.push_back(0.1 * double(i));
    r.stderrs.push_back(std::sqrt(var[i]));
  }
  return r;
}

}  // namespace

TEST_CASE("record-phase bias: the amplitude times 1 - h/2, h the harmonic mean of the phases' variances",
          "[likelihood][record_phases]") {
  const std::vector<double> var{0.01, 0.02, 0.04, 0.04};
  likelihood::Result r = phases_result(0.12, 4e-6, var);
  const double h = 4.0 / (1 / 0.01 + 1 / 0.02 + 1 / 0.04 + 1 / 0.04);  // 0.02
  const double f = likelihood::detail::correct_record_phase_bias(r);
  CHECK(f == Approx(1.0 - h / 2).epsilon(1e-14));
  CHECK(r.values[0] == Approx(0.12 * f).epsilon(1e-14));
  CHECK(r.stderrs[0] == Approx(2e-3 * f).epsilon(1e-14));
  CHECK(r.covariance(0, 0) == Approx(4e-6 * f * f).epsilon(1e-14));
  CHECK(r.covariance(0, 1) == Approx(1e-6 * f).epsilon(1e-14));
  CHECK(r.covariance(1, 0) == Approx(1e-6 * f).epsilon(1e-14));
  CHECK(r.covariance(1, 1) == 0.01);  // the phases are not touched
  CHECK(r.values[1] == 0.0);
  const Effect* e = r.model.model.find_effect(EffectId::HarmonicForcing);
  REQUIRE(e);
  CHECK(e->params.at("amplitude") == r.values[0]);
  CHECK(e->stderr_.at("amplitude") == r.stderrs[0]);

  likelihood::Result none = phases_result(0.12, 4e-6, {});  // one shared phase: nothing to correct
  CHECK(likelihood::detail::correct_record_phase_bias(none) == 1.0);
  CHECK(none.values[0] == 0.12);
  likelihood::Result lost = phases_result(0.12, 4e-6, {2.0, 3.0});  // phases not determined
  CHECK(likelihood::detail::correct_record_phase_bias(lost) == 1.0);
}

TEST_CASE("record-phase bias: refine refuses record phases it would not fit", "[likelihood][record_phases]") {
  likelihood::ObservedModel start{vehs_lik_test::model(R"({"drift": {"x": -1.0, "y": -0.2}, "diffusion": {"1": 0.04}})"),
                                  0.0, {0.3, 1.0}};
  Effect e;
  e.id = EffectId::HarmonicForcing;
  e.params = {{"amplitude", 0.1}, {"omega", 0.8}, {"phase", 0.0}};
  start.model.effects.push_back(e);
  const Dataset d = vehs_lik_test::simulate(start.model, 0.1, 2, 50.0, 7, 0.0);
  likelihood::RefineOptions o;  // per_record_phase false
  try {
    (void)likelihood::refine(start, d, o);
    FAIL("refine accepted record phases with per_record_phase false");
  } catch (const Error& err) {
    const std::string what = err.what();
    CHECK(what.find("per_record_phase is false") != std::string::npos);
  }
}

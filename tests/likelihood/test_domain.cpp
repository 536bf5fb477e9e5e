// The catalogue's domain applied to a maximum-likelihood result (detail/domain.hpp): a negative
// forcing amplitude is the positive one half a period later; any other estimate outside the
// domain is refused with one line naming it, its estimate and its standard error.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "vehs/core/error.hpp"
#include "vehs/likelihood/detail/domain.hpp"

using namespace vehs;

namespace {

likelihood::Result result_with(Effect e) {
  likelihood::Result r;
  r.model.model.drift = {{Term::parse("x"), -1.0}, {Term::parse("y"), -0.1}};
  r.model.model.diffusion = {{Term::parse("1"), 0.04}};
  r.model.model.effects.push_back(std::move(e));
  return r;
}

}  // namespace

TEST_CASE("domain: a coupling below 0 is refused with one line naming it and its standard error",
          "[likelihood][domain]") {
  Effect e;
  e.id = EffectId::ElectromechanicalCoupling;
  e.params = {{"lambda", 0.5}, {"coupling", -950.0}};
  e.stderr_ = {{"lambda", 0.1}, {"coupling", 340.0}};
  likelihood::Result r = result_with(e);
  std::string what;
  try {
    likelihood::detail::respect_domain(r);
  } catch (const Error& err) {
    what = err.what();
  }
  INFO(what);
  CHECK(what.find("electromechanical_coupling.coupling = -950") != std::string::npos);
  CHECK(what.find("outside its domain (>= 0)") != std::string::npos);
  CHECK(what.find("(standard error 340)") != std::string::npos);
  CHECK(what.find('\n') == std::string::npos);

  e.params["coupling"] = 0.0;  // the boundary is inside
  likelihood::Result ok = result_with(e);
  CHECK_NOTHROW(likelihood::detail::respect_domain(ok));
}

TEST_CASE("domain: a negative forcing amplitude becomes the positive one at phase + pi", "[likelihood][domain]") {
  Effect e;
  e.id = EffectId::HarmonicForcing;
  e.params = {{"amplitude", -0.2}, {"omega", 1.3}, {"phase", 0.5}};
  likelihood::Result r = result_with(e);
  r.parameters = {likelihood::ParameterInfo{}};
  r.parameters[0].name = "harmonic_forcing.amplitude";
  r.values = {-0.2};
  r.covariance = Eigen::MatrixXd::Constant(1, 1, 0.01);
  likelihood::detail::respect_domain(r);
  const Effect* f = r.model.model.find_effect(EffectId::HarmonicForcing);
  REQUIRE(f);
  CHECK(f->params.at("amplitude") == 0.2);
  CHECK(f->params.at("phase") == Approx(0.5 - M_PI).margin(1e-12));
  CHECK(r.values[0] == 0.2);
  CHECK(r.covariance(0, 0) == 0.01);
}

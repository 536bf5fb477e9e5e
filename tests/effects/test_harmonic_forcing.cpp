// harmonic_forcing (vehs/effects/harmonic_forcing.hpp): its force, time derivative, parameter
// derivatives on Jets and record force against direct evaluation; catalogue entry and units
// from the type.
#include <catch2/catch.hpp>

#include <ceres/jet.h>

#include <cmath>
#include <vector>

#include "vehs/core/model.hpp"
#include "vehs/core/scaling.hpp"
#include "vehs/effects/from_model.hpp"
#include "vehs/effects/harmonic_forcing.hpp"

using vehs::effects::HarmonicForcing;

TEST_CASE("harmonic_forcing force and its time derivative", "[effects][harmonic_forcing]") {
  const HarmonicForcing<double> h{0.7, 3.0, 0.4};
  CHECK(h.force(0.0) == Approx(0.7 * std::cos(0.4)).epsilon(1e-15));
  CHECK(h.force(2.0 * M_PI / 3.0) == Approx(h.force(0.0)).epsilon(1e-12));  // one period later
  const double e = 1e-6;
  for (double t : {0.0, 0.3, 1.7})
    CHECK(h.force_dt(t) == Approx((h.force(t + e) - h.force(t - e)) / (2 * e)).margin(1e-7));
  CHECK(h.rate() == 3.0);
  // derivatives with respect to the parameters (the likelihood's gradient)
  using J = ceres::Jet<double, 3>;
  const HarmonicForcing<J> hj{J(0.7, 0), J(3.0, 1), J(0.4, 2)};
  const double t = 0.9;
  const J f = hj.force(t);
  CHECK(f.a == h.force(t));
  CHECK(f.v[0] == Approx(std::cos(3.0 * t + 0.4)));
  CHECK(f.v[1] == Approx(-0.7 * t * std::sin(3.0 * t + 0.4)));
  CHECK(f.v[2] == Approx(-0.7 * std::sin(3.0 * t + 0.4)));
  std::vector<double> out(5, 1.0);
  vehs::effects::add_harmonic_forcing_record_force(h, 0.5, 0.1, out.size(), out.data());
  for (std::size_t i = 0; i < out.size(); ++i) CHECK(out[i] == Approx(1.0 + h.force(0.5 + 0.1 * double(i))));
}

TEST_CASE("harmonic_forcing catalogue entry and units come from its type", "[effects][harmonic_forcing]") {
  const vehs::EffectSpec& spec = vehs::effect_spec(vehs::EffectId::HarmonicForcing);
  CHECK(spec.name == HarmonicForcing<double>::name);
  REQUIRE(spec.params.size() == 3);
  CHECK(spec.params[2].name == "phase");
  CHECK(spec.params[2].default_value == 0.0);
  const vehs::Scales s{2e-3, 0.25};
  CHECK(vehs::effect_parameter_scale(vehs::EffectId::HarmonicForcing, "amplitude", s) == Approx(2e-3 / 0.0625));
  CHECK(vehs::effect_parameter_scale(vehs::EffectId::HarmonicForcing, "omega", s) == Approx(4.0));
  CHECK(vehs::effect_parameter_scale(vehs::EffectId::HarmonicForcing, "phase", s) == 1.0);
  vehs::Effect e{vehs::EffectId::HarmonicForcing, {{"amplitude", 2.0}, {"omega", 5.0}}, {}};
  CHECK(vehs::effects::from_effect<HarmonicForcing>(e).phase == 0.0);
}

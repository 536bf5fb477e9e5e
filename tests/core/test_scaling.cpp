#include <catch2/catch.hpp>

#include <cmath>

#include "vehs/core/model_builder.hpp"
#include "vehs/core/scaling.hpp"

namespace {

vehs::Model every_kind_of_term() {
  vehs::Model m = vehs::Model::paper(0.1, {{1, 1.0}, {3, -7.7}, {5, 16.3}}, 0.02, 0.01);
  m.drift.push_back({vehs::Term::monomial(2, 1), -0.3});
  m.drift.push_back({vehs::Term::monomial(0, 3), -0.2});
  m.drift.push_back({vehs::Term::sign_y(), -0.05});
  m.drift.push_back({vehs::Term::y_abs_y(), -0.4});
  m.drift.push_back({vehs::Term::drive(), 1.5});
  m.diffusion.push_back({vehs::Term::monomial(0, 2), 0.003});
  vehs::canonicalize(m.drift, "drift");
  vehs::canonicalize(m.diffusion, "diffusion");
  return m;
}

}  // namespace

// Dimensional analysis, checked on the functions themselves: with x = L x̃, y = (L/T) ỹ,
// u = U ũ, the physical drift is (L/T²) times the internal one and the diffusion (L²/T³) times.
TEST_CASE("to_physical turns an internal model into the same dynamics in physical units", "[scaling]") {
  const vehs::Scales s{1e-3, 1e-2, 10.0};
  const vehs::Model internal = every_kind_of_term();
  const vehs::Model physical = vehs::to_physical(internal, s);
  for (double xt : {-1.3, -0.2, 0.7, 1.1})
    for (double yt : {-0.9, 0.0, 0.4})
      for (double ut : {-1.0, 0.5}) {
        const double x = s.length * xt, y = s.length / s.time * yt, u = s.input * ut;
        const double acc = s.length / (s.time * s.time);
        CHECK(physical.b2(x, y, u) == Approx(acc * internal.b2(xt, yt, ut)).epsilon(1e-12));
        CHECK(physical.a22(x, y) ==
              Approx(acc * acc * s.time * internal.a22(xt, yt)).epsilon(1e-12));
      }
  const vehs::Model back = vehs::to_internal(physical, s);
  for (std::size_t i = 0; i < internal.drift.size(); ++i)
    CHECK(back.drift[i].coef == Approx(internal.drift[i].coef).epsilon(1e-14));
}

TEST_CASE("standard errors, covariances and effect parameters carry their units", "[scaling]") {
  const vehs::Scales s{1e-3, 0.1, 1.0};
  vehs::Model m = vehs::Model::paper(0.1, {{1, 1.0}}, 0.02);
  m.drift_stderr["x"] = 0.01;
  m.covariance.names = {"drift[x]", "diffusion[1]", "impact_stop.gap"};
  m.covariance.matrix = {1e-4, 2e-6, 0, 2e-6, 1e-6, 0, 0, 0, 4e-4};
  vehs::Effect stop;
  stop.id = vehs::EffectId::ImpactStop;
  stop.params = {{"k_stop", 50.0}, {"gap", 1.2}, {"gap_neg", 1.1}};
  stop.stderr_ = {{"gap", 0.02}};
  m.effects.push_back(stop);
  const vehs::Model p = vehs::to_physical(m, s);
  const double fx = 1.0 / (s.time * s.time), f1 = s.length * s.length / std::pow(s.time, 3);
  CHECK(p.drift_coef("x") == Approx(-1.0 * fx));
  CHECK(p.drift_stderr.at("x") == Approx(0.01 * fx));
  CHECK(p.covariance(0, 1) == Approx(2e-6 * fx * f1));
  CHECK(p.covariance(2, 2) == Approx(4e-4 * s.length * s.length));
  CHECK(p.effects[0].params.at("gap") == Approx(1.2e-3));
  CHECK(p.effects[0].params.at("k_stop") == Approx(50.0 / (s.time * s.time)));
  CHECK(p.effects[0].stderr_.at("gap") == Approx(0.02e-3));
}

TEST_CASE("natural scales are powers of ten and follow a change of units exactly", "[scaling]") {
  vehs::Dataset d;
  vehs::Record r;
  r.dt = 0.05;  // ω = 1 per time unit
  r.size = 2000;
  d.records.push_back(r);
  for (std::size_t i = 0; i < r.size; ++i) d.x.push_back(0.7 * std::sin(0.05 * static_cast<double>(i)));
  const vehs::Scales one = vehs::natural_scales(d);
  CHECK(one.is_identity());  // RMS 0.49 and 1/ω ≈ 1: already O(1)
  vehs::Dataset mm = d;
  for (auto& x : mm.x) x *= 1000.0;
  for (auto& rec : mm.records) rec.dt *= 1e-3;  // a thousand times faster
  const vehs::Scales s = vehs::natural_scales(mm);
  CHECK(s.length == 1000.0);
  CHECK(s.time == Approx(one.time * 1e-3));
  const vehs::Dataset internal = vehs::to_internal(mm, s);
  CHECK(internal.x[17] == Approx(d.x[17] / one.length).epsilon(1e-15));
  CHECK(internal.records[0].dt == Approx(d.records[0].dt / one.time).epsilon(1e-15));
}

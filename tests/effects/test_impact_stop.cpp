// impact_stop (vehs/effects/impact_stop.hpp): its force, derivative, potential, Gaussian
// expectation and record shape against independent evaluations (finite differences, quadrature),
// the same on doubles, SIMD lanes and Jets; its catalogue entry and units come from the type.
#include <catch2/catch.hpp>

#include <ceres/jet.h>

#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "vehs/core/model.hpp"
#include "vehs/core/scaling.hpp"
#include "vehs/effects/from_model.hpp"
#include "vehs/effects/impact_stop.hpp"

using vehs::effects::ImpactStop;

namespace {
const ImpactStop<double> kStop{400.0, 0.8, 1.1};
}

TEST_CASE("impact_stop force is minus the potential's slope and zero between the stops", "[effects][impact_stop]") {
  CHECK(kStop.force(0.0) == 0.0);
  CHECK(kStop.force(0.79) == 0.0);
  CHECK(kStop.force(-1.09) == 0.0);
  CHECK(kStop.force(1.3) == Approx(-400.0 * 0.5).epsilon(1e-14));
  CHECK(kStop.force(-1.6) == Approx(400.0 * 0.5).epsilon(1e-14));
  const double h = 1e-6;
  for (double x : {-2.0, -1.3, -0.5, 0.3, 0.95, 1.7}) {
    const double dU = (kStop.potential(x + h) - kStop.potential(x - h)) / (2 * h);
    CHECK(kStop.force(x) == Approx(-dU).margin(1e-6));
    const double dF = (kStop.force(x + h) - kStop.force(x - h)) / (2 * h);
    CHECK(kStop.force_dx(x) == Approx(dF).margin(1e-6));
  }
  CHECK(kStop.potential(0.0) == 0.0);
  CHECK(kStop.stiffness() == 400.0);
  for (const auto& piece : kStop.outer_pieces())
    CHECK(piece.slope == -400.0);
  CHECK(kStop.outer_pieces()[0].slope * 1.5 + kStop.outer_pieces()[0].offset == Approx(kStop.force(1.5)));
  CHECK(kStop.outer_pieces()[1].slope * -1.5 + kStop.outer_pieces()[1].offset == Approx(kStop.force(-1.5)));
}

TEST_CASE("impact_stop on SIMD lanes and Jets equals the scalar force", "[effects][impact_stop]") {
  Eigen::Array<double, 4, 1> x;
  x << -1.5, -0.2, 0.8, 1.2;
  const Eigen::Array<double, 4, 1> f = kStop.force(x), d = kStop.force_dx(x);
  for (int l = 0; l < 4; ++l) {
    CHECK(f[l] == kStop.force(x[l]));
    CHECK(d[l] == kStop.force_dx(x[l]));
  }
  using J = ceres::Jet<double, 1>;
  const ImpactStop<J> jet{J(400.0), J(0.8), J(1.1)};
  for (double xv : {-1.5, 0.3, 1.2}) {
    const J out = jet.force(J(xv, 0));
    CHECK(out.a == kStop.force(xv));
    CHECK(out.v[0] == kStop.force_dx(xv));
  }
}

TEST_CASE("impact_stop Gaussian expectation equals quadrature of its force", "[effects][impact_stop]") {
  for (double m : {-1.4, 0.0, 0.7, 1.0})
    for (double s : {0.05, 0.3, 1.0}) {
      // trapezoid over ±12 sd on 200 001 points: error far below the tolerance
      const int n = 200001;
      const double lo = m - 12 * s, h = 24 * s / (n - 1);
      double ef = 0.0, ed = 0.0;
      for (int i = 0; i < n; ++i) {
        const double x = lo + i * h, z = (x - m) / s;
        const double w = (i == 0 || i == n - 1 ? 0.5 : 1.0) * h * std::exp(-0.5 * z * z) / (s * std::sqrt(2 * M_PI));
        ef += w * kStop.force(x);
        ed += w * kStop.force_dx(x);
      }
      const auto e = kStop.expectation(m, s);
      CHECK(e.force == Approx(ef).margin(1e-6 * 400));
      CHECK(e.force_dx == Approx(ed).margin(1e-4 * 400));
    }
}

TEST_CASE("impact_stop record shape is the force seen through the ULI kernel", "[effects][impact_stop]") {
  // a path linear in time crossing the positive stop: x(t) = 0.5 + 0.1 t, samples t = 0 … 10
  std::vector<double> x(11);
  for (int i = 0; i < 11; ++i) x[static_cast<std::size_t>(i)] = 0.5 + 0.1 * i;
  std::vector<double> plain(11), tent(11);
  vehs::effects::impact_stop_record_shape(x.data(), x.size(), 0.8, 1.1, 0, plain.data());
  vehs::effects::impact_stop_record_shape(x.data(), x.size(), 0.8, 1.1, 2, tent.data());
  const ImpactStop<double> unit{1.0, 0.8, 1.1};
  for (std::size_t i = 0; i < x.size(); ++i) CHECK(plain[i] == unit.force(x[i]));
  // kernel average at sample 3 (stride 2): ∫ (2 − |s|)/4 · force(x(3 + s)) ds over [−2, 2]
  double ref = 0.0;
  const int n = 400001;
  for (int i = 0; i < n; ++i) {
    const double s = -2.0 + 4.0 * i / (n - 1), w = (i == 0 || i == n - 1 ? 0.5 : 1.0) * 4.0 / (n - 1);
    ref += w * (2.0 - std::abs(s)) / 4.0 * unit.force(0.5 + 0.1 * (3 + s));
  }
  CHECK(tent[3] == Approx(ref).margin(1e-9));
  CHECK(tent[3] != plain[3]);  // the kink near sample 3 is smoothed
  std::vector<double> sum(11, 1.0);
  vehs::effects::add_impact_stop_record_force(kStop, x.data(), x.size(), 2, sum.data());
  std::vector<double> shape(11);
  vehs::effects::impact_stop_record_shape(x.data(), x.size(), 0.8, 1.1, 2, shape.data());
  for (std::size_t i = 0; i < x.size(); ++i) CHECK(sum[i] == Approx(1.0 + 400.0 * shape[i]));
}

TEST_CASE("impact_stop catalogue entry and units come from its type", "[effects][impact_stop]") {
  const vehs::EffectSpec& spec = vehs::effect_spec(vehs::EffectId::ImpactStop);
  CHECK(spec.name == ImpactStop<double>::name);
  CHECK(spec.physics == ImpactStop<double>::physics);
  REQUIRE(spec.params.size() == ImpactStop<double>::params.size());
  for (std::size_t i = 0; i < spec.params.size(); ++i) CHECK(spec.params[i].name == ImpactStop<double>::params[i].name);
  const vehs::Scales s{2e-3, 0.25};  // length 2 mm, time 0.25 s
  CHECK(vehs::effect_parameter_scale(vehs::EffectId::ImpactStop, "k_stop", s) == Approx(1.0 / (0.25 * 0.25)));
  CHECK(vehs::effect_parameter_scale(vehs::EffectId::ImpactStop, "gap", s) == Approx(2e-3));
  vehs::Effect e{vehs::EffectId::ImpactStop, {{"k_stop", 5.0}, {"gap", 0.3}}, {}};
  const auto from = vehs::effects::from_effect<ImpactStop>(e);
  CHECK(from.gap_neg == 0.3);  // defaults to gap
}

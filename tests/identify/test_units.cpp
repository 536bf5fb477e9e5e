// Unit invariance of identification: the same record in m, mm and non-dimensional gives the same
// model up to the unit conversion, with finite standard errors and the covariance of the
// estimates; and the Silverbox data in volts (the repository's real data) get finite errors.
#include <catch2/catch.hpp>

#include <cmath>

#include "identify/identify_fixtures.hpp"
#include "vehs/core/scaling.hpp"
#include "vehs/io/measurements.hpp"

namespace {

/// The dataset in physical units: x·L, time·T.
vehs::Dataset in_units(const vehs::Dataset& d, double L, double T) {
  vehs::Dataset p = d;
  for (auto& x : p.x) x *= L;
  for (auto& r : p.records) r.dt *= T, r.t0 *= T;
  return p;
}

}  // namespace

TEST_CASE("identification is invariant to the units of x and t", "[identify][units]") {
  const vehs::Model truth = vehs_test::paper_truth();
  const vehs::Dataset nd = vehs_test::simulate(truth, 0.005, 1, 8, 40000, 71);
  vehs::identify::Options o;
  const double L = 2e-3, T = 0.02;  // 1 unit of x = 2 mm, 1 unit of time = 20 ms
  const auto a = vehs::identify::identify(nd, o).model;
  const auto m = vehs::identify::identify(in_units(nd, L, T), o).model;
  const auto mm = vehs::identify::identify(in_units(nd, 1e3 * L, T), o).model;
  for (const auto* model : {&a, &m, &mm}) vehs_test::check_written_covariance(*model);
  const vehs::Scales s{L, T, 1.0};
  const vehs::Model m_back = vehs::to_internal(m, s);
  const vehs::Model mm_back = vehs::to_internal(mm, vehs::Scales{1e3 * L, T, 1.0});
  REQUIRE(vehs::terms_of(m.drift) == vehs::terms_of(a.drift));
  REQUIRE(vehs::terms_of(mm.drift) == vehs::terms_of(a.drift));
  REQUIRE(vehs::terms_of(m.diffusion) == vehs::terms_of(a.diffusion));
  for (std::size_t i = 0; i < a.drift.size(); ++i) {
    const std::string n = a.drift[i].term.name();
    CAPTURE(n);
    const double se = a.drift_stderr.at(n);
    // m and mm map to the same internal numbers (up to one rounding): equal to 1e-9 SE
    CHECK(std::abs(m_back.drift[i].coef - mm_back.drift[i].coef) < 1e-9 * se);
    // non-dimensional data are fitted unscaled, the metric ones on data scaled by 2 and 0.2:
    // the estimator is equivariant, so only rounding separates them
    CHECK(std::abs(m_back.drift[i].coef - a.drift[i].coef) < 1e-6 * se);
    CHECK(m_back.drift_stderr.at(n) == Approx(se).epsilon(1e-6));
  }
  for (std::size_t i = 0; i < a.diffusion.size(); ++i) {
    const std::string n = a.diffusion[i].term.name();
    CHECK(std::abs(m_back.diffusion[i].coef - a.diffusion[i].coef) < 1e-6 * a.diffusion_stderr.at(n));
  }
  CHECK(m.fit->sampling.dt == Approx(0.005 * T));
}

TEST_CASE("the Silverbox data in volts get finite standard errors", "[identify][units][silverbox]") {
  vehs::ReadOptions ro;
  ro.x_column = "V2";
  ro.u_column = "V1";
  ro.require_u = true;
  ro.dt = 0.0016384;
  vehs::Dataset d = vehs::read_measurements(VEHS_SOURCE_DIR "/data/silverbox/SNLS80mV.csv", ro);
  vehs::subtract_record_means(d);
  vehs::identify::Options o;
  o.drift_library.clear();
  for (const char* t : {"1", "x", "x^2", "x^3", "y", "x*y", "x^2*y", "u"}) o.drift_library.push_back(vehs::Term::parse(t));
  o.diffusion_library = {vehs::Term::parse("1"), vehs::Term::parse("x^2")};
  const auto r = vehs::identify::identify(d, o);
  for (const auto& [n, se] : r.model.drift_stderr) CHECK(std::isfinite(se));
  for (const auto& [n, se] : r.model.diffusion_stderr) CHECK(std::isfinite(se));
  vehs_test::check_written_covariance(r.model);
  // the resonance near 60 Hz: k1 = −drift[x] ≈ (2π·60)² within a factor 2
  const double k1 = -r.model.drift_coef("x");
  CHECK(k1 > 0.5 * std::pow(2 * M_PI * 60, 2));
  CHECK(k1 < 2.0 * std::pow(2 * M_PI * 60, 2));
}

TEST_CASE("a dynamic effect's parameters carry their units: impact stops in m and non-dimensional", "[identify][units][dynamic]") {
  vehs::Model truth = vehs_test::hidden_effect_potential("bistable");
  vehs::Effect stop;
  stop.id = vehs::EffectId::ImpactStop;
  stop.params = {{"k_stop", 50.0}, {"gap", 1.3}, {"gap_neg", 1.25}};
  vehs::add_effect(truth, stop, "truth");
  const vehs::Dataset nd = vehs_test::simulate_hidden(truth, 31, 4, 30000);
  const auto o = vehs_test::baseline_options({vehs::EffectId::ImpactStop});
  const double L = 2e-3, T = 0.05;  // data in m and s
  const auto a = vehs::identify::identify(nd, o).model;
  const auto m = vehs::identify::identify(in_units(nd, L, T), o).model;
  REQUIRE(a.effects.size() == 1);
  REQUIRE(m.effects.size() == 1);
  const vehs::Effect& ea = a.effects[0];
  const vehs::Effect& em = m.effects[0];
  // equivariant up to rounding (the fit runs on data scaled by 2 in x and 0.5 in time)
  for (const char* p : {"gap", "gap_neg"}) {
    CAPTURE(p);
    CHECK(std::abs(em.param(p) / L - ea.param(p)) < 1e-4 * ea.stderr_.at(p));
    CHECK(em.stderr_.at(p) / L == Approx(ea.stderr_.at(p)).epsilon(1e-4));
  }
  CHECK(std::abs(em.param("k_stop") * T * T - ea.param("k_stop")) < 1e-4 * ea.stderr_.at("k_stop"));
  for (const auto& [n, se] : m.drift_stderr) CHECK(std::isfinite(se));
}

namespace vehs::identify::detail {
std::string noise_share_text(double share);  // src/identify/estimator_choice.hpp (internal)
}

TEST_CASE("a saturated sensor-noise reading is not stated as a share", "[identify][noise_share]") {
  using vehs::identify::detail::noise_share_text;
  // 6 (rho_2k - rho_3k) >= 1 is clamped to 1: pure white noise, never a record with motion
  CHECK(noise_share_text(1.0).find("100 %") == std::string::npos);
  CHECK(noise_share_text(1.0).find("not resolved") != std::string::npos);
  CHECK(noise_share_text(0.12).find("about 12 %") != std::string::npos);
}

// diagnose(): exact identities of the lens, calibration over seeds (true and fitted models),
// detection and localisation of missing effects, suspects, reproducibility and bad inputs.
// Data are simulated with parameters the code under test never sees; baselines are fitted by
// identify on restricted libraries.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "diagnose_fixtures.hpp"
#include "vehs/core/parallel.hpp"
#include "vehs/core/error.hpp"

using namespace diag_test;
using vehs::diagnose::diagnose;
using vehs::diagnose::Result;

namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const vehs::Error& e) {
    return e.what();
  }
  return "";
}

const vehs::diagnose::Component& component(const Result& r, const std::string& name) {
  for (const auto& c : r.components)
    if (c.name == name) return c;
  FAIL("no component " << name);
  throw;
}

std::string describe(const Result& r) {
  std::string s = vehs::enum_to_string(vehs::diagnose::kVerdictNames, r.verdict) + " score " +
                  std::to_string(r.score) + ":";
  for (const auto& c : r.components)
    s += " " + c.name + " p=" + (c.test.available ? std::to_string(c.test.p_value) : "n/a");
  s += " | suspects:";
  for (const auto& sp : r.suspects.ranked)
    s += " " + sp.effect + " " + std::to_string(sp.evidence) + " (z " + std::to_string(sp.z) + ")";
  return s;
}

vehs::Model with_term(vehs::Model m, const std::string& term, double coef) {
  m.drift.push_back({vehs::Term::parse(term), coef});
  vehs::canonicalize(m.drift, "test");
  return m;
}

/// The v centre of the map column with the largest mean z² of the residual mean.
double failure_v(const Result& r) {
  int best = -1;
  for (std::size_t j = 0; j < r.map.v_profile_mean.size(); ++j)
    if (std::isfinite(r.map.v_profile_mean[j]) &&
        (best < 0 || r.map.v_profile_mean[j] > r.map.v_profile_mean[static_cast<std::size_t>(best)]))
      best = static_cast<int>(j);
  return r.map.v_lo + (best + 0.5) * (r.map.v_hi - r.map.v_lo) / r.map.nv;
}

}  // namespace

TEST_CASE("lens identity: on Euler-Maruyama data the forward residuals of the true model are the "
          "simulator's standard normals", "[diagnose][lens]") {
  // x_{i+1} = x_i + y_i dt and y_{i+1} = y_i + b2 dt + sqrt(a22 dt) ξ make the forward kinematics
  // exact: v = y_i, a = b2(x_i, y_i) + sqrt(a22/dt) ξ_i, so r = ξ_i whatever b2 and a22 are.
  DataSpec s;
  s.records = 4;
  s.samples = 50000;
  s.scheme = vehs::sim::Scheme::EulerMaruyama;
  const auto m = bistable();
  const auto d = simulate(m, s);
  vehs::diagnose::Lens lens;
  lens.kinematics = vehs::diagnose::Kinematics::Forward;
  lens.dt = s.dt;
  const vehs::diagnose::ModelLens ml(m, lens);
  double n = 0, s1 = 0, s2 = 0, s4 = 0, lag = 0, prev = 0;
  for (const auto& rec : d.records) {
    const double* x = d.x_of(rec);
    for (std::size_t i = 0; i + 2 < rec.size; ++i) {
      double xi, v, a;
      lens.at(x, i, xi, v, a);
      bool ok = false;
      const double r = ml.residual(xi, v, a, 0.0, 0.0, ok);
      REQUIRE(ok);
      if (i > 0) lag += r * prev;
      prev = r;
      n += 1, s1 += r, s2 += r * r, s4 += r * r * r * r;
    }
  }
  const double mean = s1 / n, var = s2 / n - mean * mean;
  // four checks of n = 2·10⁵ standard normals (mean, variance, kurtosis, lag-1 product), each
  // asymptotically normal with the sd used: z_bound(4) = 4.22 sd each, 1e-4 in all (was 4: 2.5e-4)
  const double zb = vehs_test::z_bound(4);
  CHECK(std::abs(mean) < zb / std::sqrt(n));
  CHECK(std::abs(var - 1.0) < zb * std::sqrt(2.0 / n));
  CHECK(std::abs(s4 / n / (var * var) - 3.0) < zb * std::sqrt(24.0 / n));
  CHECK(std::abs(lag / n) < zb / std::sqrt(n));
}

TEST_CASE("calibration: the true model is adequate on its own data for at least 7 of 10 seeds",
          "[diagnose][calibration]") {
  // 10 seeds, scheme-consistent (the paper's rk4_euler at the recorded step) and continuous-time
  // data (sensor sampling a finely integrated process; ULI lens, taylor15 twins)
  int adequate = 0, runs = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    DataSpec s;
    s.records = 32;
    s.samples = 6000;
    s.seed = 5000 + seed;
    if (seed > 6) {
      s.substeps = 20;
      s.dt = 0.02;
    }
    const auto d = simulate(bistable(), s);
    auto o = fast_options(seed);
    o.suspects.enabled = false;
    o.fpk = false;
    const Result r = diagnose(bistable(), d, o);
    UNSCOPED_INFO("seed " << seed << ": " << describe(r));
    tally_result(seed > 6 ? "continuous" : "scheme", r);
    // the lens follows the sampling diagnosis, whose margins are ≥ 25 sd (test_identify.cpp)
    CHECK(r.lens.kinematics == (seed > 6 ? vehs::diagnose::Kinematics::Central : vehs::diagnose::Kinematics::Forward));
    adequate += r.adequate();
    ++runs;
  }
  // The verdict's family-wise false-alarm level is α = 1 %; granting the p-values a calibration
  // error up to 2 × α, P(Bin(10, 0.98) < 7) = 3.1e-5, so at least 7 of 10 seeds must be adequate
  // (the former 9 of 10 failed with 4e-3 even at exactly 1 %). Measured over seed shifts
  // (scripts/seed-study.sh on "[calibration]"): the adequate fraction is quoted in bench/results/.
  CHECK(adequate >= vehs_test::binomial_floor(10, 0.98));
}

TEST_CASE("calibration: a baseline fitted to clean data is adequate for at least 5 of 8 seeds and "
          "no suspect is claimed", "[diagnose][calibration]") {
  int adequate = 0, held_out = 0, significant = 0;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    DataSpec s;
    s.records = 32;
    s.samples = 6000;
    s.seed = 6000 + seed;
    const auto d = simulate(bistable(), s);
    const auto m = fit(d, {"x", "x^3", "y"}, {"1", "x^2"});
    auto o = fast_options(seed);
    o.parameter_draws = 6;
    o.fpk = false;
    o.suspects.enabled = seed <= 4;
    const Result r = diagnose(m, d, o);
    UNSCOPED_INFO("seed " << seed << ": " << describe(r));
    CHECK(r.parameter_draws == 6);  // the model reports standard errors: its uncertainty is propagated
    tally_result("fitted", r);
    adequate += r.adequate();
    for (const auto& sp : r.suspects.ranked) {
      significant += sp.significant;
      held_out += sp.held_out_significant;
    }
  }
  // As above: P(Bin(8, 0.98) < 5) = 1.1e-5 (the former 7 of 8: 1.0e-2 at a 2 % false-alarm rate).
  CHECK(adequate >= vehs_test::binomial_floor(8, 0.98));
  // Held-out claims: 4 diagnoses × 8 catalogue effects, each a one-sided z > 3 on ≥ 20 blocks
  // (Student t₁₉ at worst: 3.6e-3 per effect): P(Bin(32, 3.6e-3) > 3) = 5.6e-6 (the former ≤ 1:
  // 6e-3). A claimed (significant) suspect also needs a false "inadequate" (≤ 2 %): per diagnosis
  // ≤ 0.02 × 0.03, two of four: 2e-6.
  CHECK(held_out <= 3);
  CHECK(significant <= 1);
}

TEST_CASE("missing Coulomb friction: inadequate, the map's failure sits at v = 0, coulomb_friction "
          "is the first suspect with mu recovered", "[diagnose][effects]") {
  DataSpec s;
  s.records = 32;
  s.samples = 10000;
  s.seed = 301;
  const auto truth = with_term(bistable(), "sign(y)", -0.1);  // mu = 0.1
  const auto d = simulate(truth, s);
  const auto m = fit(d, {"x", "x^3", "y"}, {"1", "x^2"});
  auto o = fast_options(1);
  o.fpk = false;
  o.score_suspects.enabled = true;  // the suspects from all the data (issue 13)
  o.score_suspects.max_samples = 1e5;
  o.score_suspects.grid = 1;  // no scan of the hidden-state effects (not the question here): half the cost
  const Result r = diagnose(m, d, o);
  INFO(describe(r));
  tally_result("baseline", r);
  tally_result_suspects(r, "coulomb_friction", "mu", 0.1);
  const double bin_v = (r.map.v_hi - r.map.v_lo) / r.map.nv;
  REQUIRE(r.score_suspects.ranked.size() > 1);
  const auto& top = r.score_suspects.ranked[0];
  vehs_test::tally("one_step log10(p / threshold)",
                   std::log10(std::max(1e-300, component(r, "one_step").test.p_value) / r.threshold));
  vehs_test::tally("failure_v / bin", std::abs(failure_v(r)) / bin_v);
  vehs_test::tally("score z", top.z);
  vehs_test::tally("score z lead", top.z - r.score_suspects.ranked[1].z);
  // Measured over 6 seed shifts (scripts/seed-study.sh, 10^5 score samples; here 5·10^4: the z
  // and the lead shrink by √2): log10(min p / threshold) −71 ± sd 11 (the score test; adequate
  // needs > 0: 6.4 sd); coulomb_friction first among the score suspects in 6 of 6, z 18.4 ± 1.4
  // ahead of the runner-up by 9.7 ± 0.7 (here ≈ 6.8 ± 0.5: 13 sd); the map's failure at
  // |v| = 0.68 ± 0.12 bins (1.5 bins: 6.8 sd); the held-out fit's μ −8.3 % ± 3.3 % (30 %: 6.6 sd).
  // Each of the four checks fails with probability < 1e-9 under a normal spread: in all ≤ 1e-4.
  // Not checked (the former KNOWN WEAKNESS, a few % to 20 % false failure per seed): the one-step
  // map's own p < threshold (log10(p / threshold) −4.2 ± 5.0) and the held-out suspects' z > 3
  // (4.5 ± 1.2) and lead (26 ± 10 nats): these data (32 × 10⁴, μ = 0.1) sit at the edge of the
  // held-out evidence; the score test on all the data is the statistic that names the friction.
  CHECK(!r.adequate());
  CHECK(std::abs(failure_v(r)) < 1.5 * bin_v);
  CHECK(top.effect == "coulomb_friction");
  CHECK(top.significant);
  bool held_out = false;
  for (const auto& sp : r.suspects.ranked)
    if (sp.effect == "coulomb_friction") {
      held_out = true;
      CHECK(sp.params.at("mu") == Approx(0.1).margin(0.03));
    }
  CHECK(held_out);
}

TEST_CASE("missing asymmetric stiffness: inadequate, asymmetric_stiffness is the first suspect",
          "[diagnose][effects]") {
  DataSpec s;
  s.records = 32;
  s.samples = 10000;
  s.seed = 401;
  const auto truth = with_term(bistable(), "x^2", -0.15);  // U' gains 0.15 x²: k2 = 0.15
  const auto d = simulate(truth, s);
  const auto m = fit(d, {"x", "x^3", "y"}, {"1", "x^2"});
  auto o = fast_options(2);
  o.fpk = false;
  const Result r = diagnose(m, d, o);
  INFO(describe(r));
  tally_result("baseline", r);
  tally_result_suspects(r, "asymmetric_stiffness", "k2", 0.15);
  // Power checks over 4 seed shifts: log10(min p / threshold) −97 to −115, the suspect first in
  // 4/4 with z 12.5 ± sd 2.1 (threshold 3: 4.5 sd, 4e-6), k2 +9.5 % ± 5 % (the 0.08 margin is
  // 53 % of 0.15: ≥ 4 sd)
  CHECK(!r.adequate());
  REQUIRE_FALSE(r.suspects.ranked.empty());
  CHECK(r.suspects.ranked[0].effect == "asymmetric_stiffness");
  CHECK(r.suspects.ranked[0].significant);
  CHECK(r.suspects.ranked[0].params.at("k2") == Approx(0.15).margin(0.08));
  // the even force is largest where |x| is large: the failing x row is away from the barrier
  double best = 0, xbest = 0;
  for (std::size_t i = 0; i < r.map.x_profile_mean.size(); ++i)
    if (std::isfinite(r.map.x_profile_mean[i]) && r.map.x_profile_mean[i] > best) {
      best = r.map.x_profile_mean[i];
      xbest = r.map.x_lo + (static_cast<double>(i) + 0.5) * (r.map.x_hi - r.map.x_lo) / r.map.nx;
    }
  CHECK(std::abs(xbest) > 0.5);
}

TEST_CASE("results do not depend on the number of threads", "[diagnose]") {
  DataSpec s;
  s.records = 16;
  s.samples = 4000;
  const auto d = simulate(bistable(), s);
  auto o = fast_options(3);
  o.suspects.enabled = false;
  o.fpk = false;
  vehs::set_threads(1);
  const Result a = diagnose(bistable(), d, o);
  vehs::set_threads(2);
  const Result b = diagnose(bistable(), d, o);
  vehs::set_threads(0);
  CHECK(a.score == b.score);
  for (std::size_t k = 0; k < a.components.size(); ++k) CHECK(a.components[k].test.p_value == b.components[k].test.p_value);
}

TEST_CASE("mismatched inputs get one-line errors naming the problem", "[diagnose][errors]") {
  DataSpec s;
  s.records = 4;
  s.samples = 2000;
  const auto d = simulate(bistable(), s);
  vehs::diagnose::Options o = fast_options(1);
  o.suspects.enabled = false;
  o.fpk = false;
  auto no_diffusion = bistable();
  no_diffusion.diffusion.clear();
  CHECK_THAT(error_of([&] { diagnose(no_diffusion, d, o); }), Catch::Contains("no diffusion terms"));
  auto with_u = with_term(bistable(), "u", 1.0);
  CHECK_THAT(error_of([&] { diagnose(with_u, d, o); }), Catch::Contains("drive term 'u'"));
  auto stated = bistable();
  stated.fit.emplace();
  stated.fit->sampling.dt = 0.001;
  stated.fit->sampling.verdict = vehs::SamplingVerdict::SchemeConsistent;
  CHECK_THAT(error_of([&] { diagnose(stated, d, o); }), Catch::Contains("sampling.dt"));
  auto expected = o;
  expected.expected_dt = 0.005;
  CHECK_THAT(error_of([&] { diagnose(bistable(), d, expected); }),
             Catch::Contains("record traj=0") && Catch::Contains("dt = 0.005"));
  auto negative = bistable();
  negative.diffusion = {{vehs::Term::parse("1"), 0.02}, {vehs::Term::parse("x^2"), -0.05}};
  CHECK_THAT(error_of([&] { diagnose(negative, d, o); }), Catch::Contains("not positive at x ="));
  vehs::Dataset tiny = d;
  tiny.records.resize(1);
  tiny.records[0].size = 500;
  CHECK_THAT(error_of([&] { diagnose(bistable(), tiny, o); }), Catch::Contains("too little data"));
  vehs::Dataset nan = d;
  nan.x[nan.records[1].offset + 17] = std::nan("");
  CHECK_THAT(error_of([&] { diagnose(bistable(), nan, o); }), Catch::Contains("sample 17") && Catch::Contains("NaN"));
  auto bad = o;
  bad.alpha = 0.7;
  CHECK_THAT(error_of([&] { diagnose(bistable(), d, bad); }), Catch::Contains("alpha"));
}

#pragma once
// Shared fixtures of the identification tests: the seed paper's penta-stable harvester (Eq. 27)
// simulated with parameters the estimator never sees, and helpers that compare a learned model
// with the truth in units of the reported standard errors.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <string>

#include <Eigen/Dense>

#include "vehs/core/model.hpp"
#include "vehs/identify/identify.hpp"
#include "vehs/io/model_file.hpp"
#include "vehs/sim/simulate.hpp"
#include "stat_bounds.hpp"

namespace vehs_test {

inline vehs::Model paper_truth() {
  return vehs::model_from_json(nlohmann::json::parse(R"({
    "drift": {"x": -1.0, "x^3": 7.7, "x^5": -16.3, "x^7": 12.5, "x^9": -3.1, "y": -0.1},
    "diffusion": {"1": 0.02, "x^2": 0.01}})"), "paper truth");
}

/// `records` records of `samples` samples at interval dt; substeps 1 with rk4_euler is the
/// paper's own scheme (Eq. 30), substeps >= 20 emulates a sensor sampling a continuous process.
/// (`seed` goes through vehs_test::seed: seed studies shift it.)
inline vehs::Dataset simulate(const vehs::Model& m, double dt, int substeps, int records,
                              std::size_t samples, std::uint64_t seed, double sensor_noise = 0.0,
                              vehs::sim::Scheme scheme = vehs::sim::Scheme::Rk4Euler) {
  vehs::sim::SimulationOptions o;
  o.dt = dt;
  o.substeps = substeps;
  o.records = records;
  o.samples = samples;
  o.seed = vehs_test::seed(seed);
  o.scheme = scheme;
  o.sensor_noise = sensor_noise;
  o.record_y = false;
  return vehs::sim::simulate(m, o);
}

inline std::set<std::string> names(const vehs::TermList& l) {
  std::set<std::string> s;
  for (const auto& tc : l) s.insert(tc.term.name());
  return s;
}

/// The |z| limit of k checks (estimate − truth)/SE of identify's estimates in one test case:
/// z_bound(k) (stat_bounds.hpp: family-wise false failure p, default 1e-4) times the spread of z
/// over seeds. identify's sandwich standard errors are calibrated but estimated: over 19 seed
/// shifts of the identify suite (scripts/seed-study.sh 50 build/tests/test_identify
/// "[identify]~[app]", stopped at 19 runs) the pooled sd of z over 83 coefficients and effect
/// parameters is 1.065 (1789 values, largest |z| 4.19; the per-quantity estimates, 0.77–1.56 on
/// 17 dof each, scatter as 83 such estimates of one common value do); the dedicated studies give
/// 0.88–1.08 (Coulomb, 50 seeds) and 0.90–1.00 (impact stops, 200 seeds). The factor 1.15 covers
/// the pooled value with its uncertainty: z_limit(8) = 1.15 × 4.37 = 5.0 (the former 3.0 failed
/// with probability ≈ 2–3 % per test case of 8 terms at sd 1.065).
inline double z_limit(int k, double p = kFalseFailure) { return 1.15 * z_bound(k, p); }

/// Largest |learned − true| / stderr over the true terms (infinite when a term is missing).
struct Deviation {
  double max_z = 0.0;
  double max_rel = 0.0;  ///< largest relative error
  std::string worst;
};

inline Deviation compare(const vehs::Model& learned, const vehs::Model& truth, bool print = true) {
  Deviation d;
  auto one = [&](const vehs::TermList& tl, const vehs::TermList& ll,
                 const std::map<std::string, double>& se, const char* kind) {
    for (const auto& tc : tl) {
      const std::string n = tc.term.name();
      const double v = vehs::coefficient(ll, tc.term);
      const auto it = se.find(n);
      const double s = it == se.end() ? NAN : it->second;
      const double z = std::abs(v - tc.coef) / s;
      const double rel = std::abs(v - tc.coef) / std::abs(tc.coef);
      tally(std::string(kind) + " " + n, (v - tc.coef) / s, (v - tc.coef) / std::abs(tc.coef));
      if (print)
        UNSCOPED_INFO(kind << " " << n << ": true " << tc.coef << ", learned " << v << " +- " << s
                           << " (z = " << (v - tc.coef) / s << ", " << 100 * rel << " %)");
      if (!(z <= d.max_z)) d.max_z = std::isfinite(z) ? std::max(d.max_z, z) : INFINITY, d.worst = n;
      d.max_rel = std::max(d.max_rel, rel);
    }
  };
  one(truth.drift, learned.drift, learned.drift_stderr, "drift");
  one(truth.diffusion, learned.diffusion, learned.diffusion_stderr, "diffusion");
  return d;
}

/// Support of a sparse selection against the truth: every true term selected; at most
/// `max_spurious` other terms in drift and diffusion together, each insignificant (|coef| ≤
/// z_limit(candidates)·SE, `candidates` the number of library terms that are not true). BIC keeps
/// a spurious term with probability ≈ P(χ²₁ > log n) each (1.4e-4 at n = 2·10⁶ rows, 3.6e-4 at
/// 3.2·10⁵), so an exact support over the 8 + 3 spurious terms of the default libraries fails
/// with ≈ 1.5e-3 per run, while two spurious terms at once have ≤ C(11, 2)·(1.4e-4)² = 1.1e-6; a
/// kept spurious term sits just above the BIC line (|t| ≈ √(log n) ≈ 3.8), and |t| > z_limit is
/// the z-check's own ≤ 1e-4. The true terms have |t| > 15 in every seed study here.
inline void check_support(const vehs::Model& learned, const vehs::Model& truth, int candidates,
                          int max_spurious = 1) {
  int spurious = 0;
  auto one = [&](const vehs::TermList& t, const vehs::TermList& l, const std::map<std::string, double>& se,
                 const char* kind) {
    const auto want = names(t);
    for (const auto& n : want) {
      INFO(kind << " term " << n);
      CHECK(names(l).count(n) == 1);
    }
    int extra = 0;
    for (const auto& tc : l) {
      const std::string n = tc.term.name();
      if (want.count(n)) continue;
      ++extra;
      const auto it = se.find(n);
      const double z = it == se.end() ? INFINITY : std::abs(tc.coef) / it->second;
      INFO("spurious " << kind << " term " << n << ": " << tc.coef << " (|t| = " << z << ")");
      CHECK(z <= z_limit(std::max(candidates, 1)));
    }
    spurious += extra;
    tally(std::string(kind) + " spurious terms", static_cast<double>(extra));
  };
  one(truth.drift, learned.drift, learned.drift_stderr, "drift");
  one(truth.diffusion, learned.diffusion, learned.diffusion_stderr, "diffusion");
  CHECK(spurious <= max_spurious);
}

inline double rel_error(const vehs::Model& learned, const vehs::Model& truth, bool diffusion,
                        const std::string& term) {
  const double t = diffusion ? truth.diffusion_coef(term) : truth.drift_coef(term);
  const double l = diffusion ? learned.diffusion_coef(term) : learned.drift_coef(term);
  return std::abs(l - t) / std::abs(t);
}

/// The Fig. 2 family's bistable (U' = −x + x³) or monostable (U' = x + x³) harvester with
/// β = 0.1, 2D = 0.02, 2Q = 0.01: the base models the dynamic-effect tests hide effects in.
inline vehs::Model hidden_effect_potential(const std::string& which) {
  const char* json = which == "bistable"
                         ? R"({"drift": {"x": 1.0, "x^3": -1.0, "y": -0.1}, "diffusion": {"1": 0.02, "x^2": 0.01}})"
                         : R"({"drift": {"x": -1.0, "x^3": -1.0, "y": -0.1}, "diffusion": {"1": 0.02, "x^2": 0.01}})";
  return vehs::model_from_json(nlohmann::json::parse(json), which);
}

/// Continuous-time records (Taylor 1.5 on 10 internal steps per dt = 0.01), x only.
inline vehs::Dataset simulate_hidden(const vehs::Model& m, std::uint64_t seed, int records = 8,
                                     std::size_t samples = 40000, double burn_in = 20.0) {
  vehs::sim::SimulationOptions o;
  o.dt = 0.01;
  o.substeps = 10;
  o.records = records;
  o.samples = samples;
  o.seed = vehs_test::seed(seed);
  o.scheme = vehs::sim::Scheme::Taylor15;
  o.burn_in = burn_in;
  o.record_y = false;
  return vehs::sim::simulate(m, o);
}

/// Impact stops drawn as the tests draw them: both gaps at a random quantile q ∈ [0.90, 0.96] of
/// |x| of the same system without stops (a free run of 2 × 20000 samples), k_stop ∈ [20, 80].
inline vehs::Effect draw_impact_stop(const vehs::Model& base, std::mt19937_64& g) {
  const vehs::Dataset free_run = simulate_hidden(base, 5, 2, 20000);
  std::vector<double> pos, neg;
  for (double v : free_run.x) (v > 0 ? pos : neg).push_back(std::abs(v));
  std::sort(pos.begin(), pos.end());
  std::sort(neg.begin(), neg.end());
  const double q = std::uniform_real_distribution<double>(0.90, 0.96)(g);
  vehs::Effect e;
  e.id = vehs::EffectId::ImpactStop;
  e.params = {{"k_stop", std::uniform_real_distribution<double>(20.0, 80.0)(g)},
              {"gap", pos[static_cast<std::size_t>(q * static_cast<double>(pos.size()))]},
              {"gap_neg", neg[static_cast<std::size_t>(q * static_cast<double>(neg.size()))]}};
  return e;
}

/// identify on the hidden-effect potentials' own terms (x, x³, y; 1, x²), sparsity off, with
/// `effects` requested (their params fitted).
inline vehs::identify::Options baseline_options(std::vector<vehs::EffectId> effects = {}) {
  vehs::identify::Options o;
  o.drift_library = {vehs::Term::parse("x"), vehs::Term::parse("x^3"), vehs::Term::parse("y")};
  o.diffusion_library = vehs::paper_diffusion_library(2);
  o.sparsity = vehs::identify::Sparsity::None;
  for (const auto id : effects) {
    vehs::Effect e;
    e.id = id;
    o.effects.push_back(e);
  }
  return o;
}

inline double uniform(std::mt19937_64& g, double a, double b) {
  return std::uniform_real_distribution<double>(a, b)(g);
}

/// Fitted effect parameter vs truth, one of k z-checks of the test case: |Δ| ≤ z_limit(k)·SE,
/// and the parameter resolved (SE ≤ `resolution` of the truth, default 15 %). The former
/// "|Δ| ≤ 15 %" was a bias check that failed with probability 2Φ(−0.15|truth|/SE) — 1 % at an SE
/// of 6 %, and most of the time for the draws whose SE exceeds 15 % (over seed shifts: colored_noise
/// tau up to 35 %, electromechanical coupling up to 15 %); the bias itself is measured over seeds
/// instead (mean relative error ± SE per parameter: test_bias_study.cpp, seed-study.sh).
inline void check_effect_param(const vehs::Effect& fitted, const std::string& name, double truth, int k,
                               double resolution = 0.15) {
  const double v = fitted.param(name);
  const double se = fitted.stderr_.at(name);
  tally(fitted.name() + "." + name, (v - truth) / se, (v - truth) / std::abs(truth));
  tally(fitted.name() + "." + name + " SE/|truth|", se / std::abs(truth));
  INFO(fitted.name() << "." << name << ": true " << truth << ", fitted " << v << " +- " << se
                     << " (z = " << (v - truth) / se << ")");
  CHECK(std::isfinite(se));
  CHECK(se > 0.0);
  CHECK(std::abs(v - truth) <= z_limit(k) * se);
  CHECK(se <= resolution * std::abs(truth));
}

/// The covariance a fitted model file carries: one entry per estimate with a standard error
/// (drift and diffusion terms, effect parameters), its diagonal the square of that standard
/// error, positive definite, and the same after a round trip through the model file.
inline void check_written_covariance(const vehs::Model& m) {
  const vehs::ParameterCovariance& c = m.covariance;
  REQUIRE_FALSE(c.empty());
  CHECK(c.invalid_reason().empty());
  std::size_t expected = 0;
  auto check_se = [&](const std::string& name, double se) {
    ++expected;
    CAPTURE(name);
    const std::size_t i = c.index_of(name);
    REQUIRE(i < c.size());
    CHECK(std::sqrt(c(i, i)) == Approx(se).epsilon(1e-9));
  };
  for (const auto& [term, se] : m.drift_stderr) check_se("drift[" + term + "]", se);
  for (const auto& [term, se] : m.diffusion_stderr) check_se("diffusion[" + term + "]", se);
  for (const auto& e : m.effects)
    for (const auto& [param, se] : e.stderr_) check_se(std::string(vehs::effect_spec(e.id).name) + "." + param, se);
  CHECK(c.size() == expected);
  Eigen::MatrixXd a(static_cast<Eigen::Index>(c.size()), static_cast<Eigen::Index>(c.size()));
  for (std::size_t i = 0; i < c.size(); ++i)
    for (std::size_t j = 0; j < c.size(); ++j) a(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = c(i, j);
  // positive definite: the correlation matrix (entries of a physical-unit covariance span 60
  // decades, too many for an eigen-solver's rounding on the covariance itself)
  const Eigen::VectorXd inv_sd = a.diagonal().cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd r = inv_sd.asDiagonal() * a * inv_sd.asDiagonal();
  CHECK(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(r).eigenvalues().minCoeff() > 1e-12);
  const vehs::Model back = vehs::model_from_json(nlohmann::json::parse(vehs::model_to_json(m).dump()), "m.json");
  CHECK(back.covariance.names == c.names);
  CHECK(back.covariance.matrix == c.matrix);
}

}  // namespace vehs_test

#pragma once
// Shared fixtures of the identification tests: the seed paper's penta-stable harvester (Eq. 27)
// simulated with parameters the estimator never sees, and helpers that compare a learned model
// with the truth in units of the reported standard errors.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <string>

#include "vehs/core/model.hpp"
#include "vehs/identify/identify.hpp"
#include "vehs/io/model_file.hpp"
#include "vehs/sim/simulate.hpp"

namespace vehs_test {

inline vehs::Model paper_truth() {
  return vehs::model_from_json(nlohmann::json::parse(R"({
    "drift": {"x": -1.0, "x^3": 7.7, "x^5": -16.3, "x^7": 12.5, "x^9": -3.1, "y": -0.1},
    "diffusion": {"1": 0.02, "x^2": 0.01}})"), "paper truth");
}

/// `records` records of `samples` samples at interval dt; substeps 1 with rk4_euler is the
/// paper's own scheme (Eq. 30), substeps >= 20 emulates a sensor sampling a continuous process.
inline vehs::Dataset simulate(const vehs::Model& m, double dt, int substeps, int records,
                              std::size_t samples, std::uint64_t seed, double sensor_noise = 0.0,
                              vehs::sim::Scheme scheme = vehs::sim::Scheme::Rk4Euler) {
  vehs::sim::SimulationOptions o;
  o.dt = dt;
  o.substeps = substeps;
  o.records = records;
  o.samples = samples;
  o.seed = seed;
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
  o.seed = seed;
  o.scheme = vehs::sim::Scheme::Taylor15;
  o.burn_in = burn_in;
  o.record_y = false;
  return vehs::sim::simulate(m, o);
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

/// Fitted effect parameter vs truth: |Δ| ≤ 3 SE and ≤ 15 %.
inline void check_effect_param(const vehs::Effect& fitted, const std::string& name, double truth) {
  const double v = fitted.param(name);
  const double se = fitted.stderr_.at(name);
  INFO(fitted.name() << "." << name << ": true " << truth << ", fitted " << v << " +- " << se
                     << " (z = " << (v - truth) / se << ")");
  CHECK(std::isfinite(se));
  CHECK(se > 0.0);
  CHECK(std::abs(v - truth) <= 3.0 * se);
  CHECK(std::abs(v - truth) <= 0.15 * std::abs(truth));
}

}  // namespace vehs_test

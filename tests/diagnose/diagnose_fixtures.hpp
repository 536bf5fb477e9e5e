#pragma once
// Shared fixtures of the diagnose tests: models with known structure, data simulated from
// parameters the code under test never sees, baselines fitted with identify on restricted
// libraries.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "vehs/core/model.hpp"
#include "vehs/diagnose/diagnose.hpp"
#include "vehs/identify/identify.hpp"
#include "vehs/io/model_file.hpp"
#include "vehs/sim/simulate.hpp"
#include "stat_bounds.hpp"

namespace diag_test {

inline vehs::Model model_of(const std::string& json) {
  return vehs::model_from_json(nlohmann::json::parse(json), "test model");
}

/// Bistable Duffing harvester (wells at ±1), the Fig. 2 family of the seed paper.
inline vehs::Model bistable() {
  return model_of(R"({"drift": {"x": 1.0, "x^3": -1.0, "y": -0.1},
                      "diffusion": {"1": 0.02, "x^2": 0.01}})");
}

struct DataSpec {
  int records = 40;
  std::size_t samples = 20000;
  double dt = 0.01;
  int substeps = 1;
  vehs::sim::Scheme scheme = vehs::sim::Scheme::Rk4Euler;
  std::uint64_t seed = 1;
  double sensor_noise = 0.0;
};

/// 16 records of 6000 samples from a continuous process (Taylor 1.5, 10 substeps): a sensor's data.
inline DataSpec sensor_records(std::uint64_t seed) {
  DataSpec s;
  s.records = 16;
  s.samples = 6000;
  s.substeps = 10;
  s.scheme = vehs::sim::Scheme::Taylor15;
  s.seed = seed;
  return s;
}

inline vehs::Dataset simulate(const vehs::Model& m, const DataSpec& s) {
  vehs::sim::SimulationOptions o;
  o.dt = s.dt;
  o.substeps = s.substeps;
  o.records = s.records;
  o.samples = s.samples;
  o.seed = vehs_test::seed(s.seed);  // seed studies shift it (stat_bounds.hpp)
  o.scheme = s.scheme;
  o.sensor_noise = s.sensor_noise;
  o.record_y = false;
  return vehs::sim::simulate(m, o);
}

/// identify with a fixed term list (the paper's model terms), sparse regression off.
inline vehs::Model fit(const vehs::Dataset& d, const std::vector<std::string>& drift,
                       const std::vector<std::string>& diffusion) {
  vehs::identify::Options o;
  o.drift_library.clear();
  o.diffusion_library.clear();
  for (const auto& t : drift) o.drift_library.push_back(vehs::Term::parse(t));
  for (const auto& t : diffusion) o.diffusion_library.push_back(vehs::Term::parse(t));
  o.sparsity = vehs::identify::Sparsity::None;
  return vehs::identify::identify(d, o).model;
}

/// Records a diagnosis for seed studies (scripts/seed-study.sh): adequate (1/0) and the smallest
/// component p-value over the verdict's threshold, as log10 (< 0: inadequate).
inline void tally_result(const std::string& label, const vehs::diagnose::Result& r) {
  double pmin = 1.0;
  for (const auto& c : r.components)
    if (c.test.available) pmin = std::min(pmin, c.test.p_value);
  vehs_test::tally(label + " adequate", r.adequate());
  vehs_test::tally(label + " log10(min p / threshold)", std::log10(std::max(pmin, 1e-300) / r.threshold));
}

/// Records the suspects of a diagnosis with a hidden `effect` for seed studies: whether it is
/// ranked first and significant, its evidence over the runner-up's, its z, and a fitted parameter
/// relative to `truth`.
inline void tally_result_suspects(const vehs::diagnose::Result& r, const std::string& effect,
                                  const std::string& param, double truth) {
  const auto& ranked = r.suspects.ranked;
  if (ranked.empty()) return;
  vehs_test::tally(effect + " first", ranked[0].effect == effect);
  vehs_test::tally(effect + " significant", ranked[0].significant);
  vehs_test::tally(effect + " z", ranked[0].z);
  if (ranked.size() > 1) vehs_test::tally(effect + " evidence lead (nats)", ranked[0].evidence - ranked[1].evidence);
  if (ranked[0].effect == effect && !param.empty())
    vehs_test::tally(effect + " " + param, ranked[0].params.at(param) / truth - 1.0,
                     ranked[0].params.at(param) / truth - 1.0);
}

/// Fast default options of the tests.
inline vehs::diagnose::Options fast_options(std::uint64_t seed) {
  vehs::diagnose::Options o;
  o.seed = vehs_test::seed(seed);
  o.replicates = 2;
  o.fpk_cells = 80;
  return o;
}

/// "name seconds, ..." of a diagnosis's stage timings (for messages).
inline std::string timings_text(const vehs::diagnose::Result& r) {
  std::string s;
  for (const auto& [stage, seconds] : r.timings) s += (s.empty() ? "" : ", ") + stage + " " + std::to_string(seconds);
  return s;
}
inline double total_seconds(const vehs::diagnose::Result& r) {
  for (const auto& [stage, seconds] : r.timings)
    if (stage == "total") return seconds;
  return 0.0;
}
/// "key = value, ..." of fitted parameters (for messages).
inline std::string params_text(const std::map<std::string, double>& params) {
  std::string s;
  for (const auto& [k, v] : params) s += (s.empty() ? "" : ", ") + k + " = " + std::to_string(v);
  return s;
}

}  // namespace diag_test

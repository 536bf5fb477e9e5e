#pragma once
// Shared fixtures of the likelihood tests: records simulated from continuous time (fine
// internal steps, a sensor sampling a continuous process) with parameters the estimator never
// sees, and checks of a fit against the truth in units of its standard errors.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "vehs/core/model.hpp"
#include "vehs/io/model_file.hpp"
#include "vehs/likelihood/refine.hpp"
#include "vehs/sim/simulate.hpp"

namespace vehs_lik_test {

inline vehs::Model model(const char* json) {
  return vehs::model_from_json(nlohmann::json::parse(json), "test model");
}

/// The bistable Duffing of issue 12: U = −x²/2 + x⁴/4, β = 0.1, 2D = 0.04.
inline vehs::Model bistable() {
  return model(R"({"drift": {"x": 1.0, "x^3": -1.0, "y": -0.1}, "diffusion": {"1": 0.04}})");
}

/// `records` records of duration `T` sampled at dt from a continuous process (Taylor 1.5 with
/// `substeps` internal steps per sample), after a burn-in, with white sensor noise `noise`.
inline vehs::Dataset simulate(const vehs::Model& m, double dt, int records, double T,
                              std::uint64_t seed, double noise = 0.0, int substeps = 40,
                              const std::vector<double>* drive = nullptr) {
  vehs::sim::SimulationOptions o;
  o.dt = dt;
  o.substeps = substeps;
  o.records = records;
  o.samples = std::size_t(std::llround(T / dt));
  o.seed = seed;
  o.scheme = vehs::sim::Scheme::Taylor15;
  o.sensor_noise = noise;
  o.record_y = false;
  o.burn_in = drive ? 0.0 : 50.0;  // (a recorded drive has no values before t = 0)
  if (drive) o.drive = *drive;
  return vehs::sim::simulate(m, o);
}

template <class Values>  // std::vector<double> or vehs::Column
double sd_of(const Values& v) {
  double m = 0.0, s = 0.0;
  for (double x : v) m += x;
  m /= double(v.size());
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / double(v.size() - 1));
}

/// Largest |estimate − truth|/SE and relative error over the given parameters (by name).
struct Check {
  double max_z = 0.0, max_rel = 0.0;
  std::string worst;
};
inline Check against(const vehs::likelihood::Result& r, const std::map<std::string, double>& truth) {
  Check c;
  for (const auto& [name, v] : truth) {
    const int i = r.find(name);
    INFO("parameter " << name);
    REQUIRE(i >= 0);
    const double est = r.values[std::size_t(i)], se = r.stderrs[std::size_t(i)];
    const double z = std::abs(est - v) / se, rel = std::abs(est - v) / std::abs(v);
    UNSCOPED_INFO(name << ": true " << v << ", fitted " << est << " +- " << se << " (z "
                       << (est - v) / se << ", " << 100.0 * rel << " %)");
    if (!(z <= c.max_z)) {
      c.max_z = std::isfinite(z) ? std::max(c.max_z, z) : INFINITY;
      c.worst = name;
    }
    c.max_rel = std::max(c.max_rel, rel);
  }
  return c;
}

/// The names of a fit's drift and diffusion parameters (its support).
inline std::vector<std::string> support(const vehs::likelihood::Result& r) {
  std::vector<std::string> s;
  for (const auto& p : r.parameters)
    if (p.kind == vehs::likelihood::ParameterKind::Drift ||
        p.kind == vehs::likelihood::ParameterKind::Diffusion ||
        p.kind == vehs::likelihood::ParameterKind::MeasurementSd)
      s.push_back(p.name);
  std::sort(s.begin(), s.end());
  return s;
}

/// Two-sided normal quantile for a per-parameter false-failure probability p: the z bound of
/// a test of k parameters with total false-failure probability ≤ 1e-4 is z(1e-4 / k).
inline double z_bound(int parameters, double total = 1e-4) {
  const double p = total / parameters;
  double lo = 0.0, hi = 10.0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
  }
  return hi;
}

}  // namespace vehs_lik_test

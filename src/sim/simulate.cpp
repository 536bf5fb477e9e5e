// First, plain implementation of the simulator (scalar, generic term evaluation).
#include "vehs/sim/simulate.hpp"

#include <chrono>
#include <cmath>
#include <random>

#include "vehs/core/error.hpp"

namespace vehs::sim {

std::string SimulationOptions::invalid_reason() const {
  if (!(dt > 0.0) || !std::isfinite(dt)) return "dt must be > 0";
  if (substeps < 1) return "substeps must be >= 1";
  if (samples < 2) return "a record needs at least 2 samples";
  if (records < 1) return "records must be >= 1";
  if (!x0.uniform && x0.values.size() != static_cast<std::size_t>(records))
    return "x0 needs one value per record";
  if (!(sensor_noise >= 0.0)) return "sensor_noise must be >= 0";
  if (!(burn_in >= 0.0)) return "burn_in must be >= 0";
  return "";
}

Dataset simulate(const Model& model, const SimulationOptions& o, SimulationSummary* summary) {
  const auto t_start = std::chrono::steady_clock::now();
  if (auto why = o.invalid_reason(); !why.empty()) throw Error("simulation: " + why);
  if (model.has_dynamic_effects()) throw Error("simulation: effects are not supported yet");
  if (o.scheme != Scheme::EulerMaruyama && o.scheme != Scheme::Rk4Euler)
    throw Error("simulation: scheme '" + enum_to_string(kSchemeNames, o.scheme) +
                "' is not available yet");
  Dataset d;
  const std::size_t n = o.samples;
  d.x.resize(n * static_cast<std::size_t>(o.records));
  if (o.record_y) d.y.resize(d.x.size());
  const double h = o.dt / o.substeps;
  const double sqh = std::sqrt(h);
  const long long burn_steps = std::llround(o.burn_in / h);
  for (int r = 0; r < o.records; ++r) {
    std::mt19937_64 gen(o.seed * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(r));
    std::normal_distribution<double> normal;
    std::uniform_real_distribution<double> uni(o.x0.lo, o.x0.hi);
    double x = o.x0.uniform ? uni(gen) : o.x0.values[static_cast<std::size_t>(r)];
    double y = o.x0.y0;
    auto b2 = [&](double xx, double yy) { return model.b2(xx, yy); };
    auto step = [&]() {
      const double a = model.a22(x, y);
      const double noise = std::sqrt(std::max(a, 0.0)) * sqh * normal(gen);
      if (o.scheme == Scheme::EulerMaruyama) {
        const double f = b2(x, y);
        x += h * y;
        y += h * f + noise;
      } else {
        const double k1x = y, k1y = b2(x, y);
        const double k2x = y + 0.5 * h * k1y, k2y = b2(x + 0.5 * h * k1x, y + 0.5 * h * k1y);
        const double k3x = y + 0.5 * h * k2y, k3y = b2(x + 0.5 * h * k2x, y + 0.5 * h * k2y);
        const double k4x = y + h * k3y, k4y = b2(x + h * k3x, y + h * k3y);
        x += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
        y += h / 6 * (k1y + 2 * k2y + 2 * k3y + k4y) + noise;
      }
    };
    for (long long s = 0; s < burn_steps; ++s) step();
    Record rec;
    rec.source = "simulation";
    rec.id = r;
    rec.dt = o.dt;
    rec.offset = static_cast<std::size_t>(r) * n;
    rec.size = n;
    for (std::size_t i = 0; i < n; ++i) {
      if (i > 0)
        for (int s = 0; s < o.substeps; ++s) step();
      if (!std::isfinite(x) || std::abs(x) > 1e6)
        throw Error("simulation: record " + std::to_string(r) + " diverged at t = " +
                    std::to_string(static_cast<double>(i) * o.dt));
      d.x[rec.offset + i] = x + (o.sensor_noise > 0 ? o.sensor_noise * normal(gen) : 0.0);
      if (o.record_y) d.y[rec.offset + i] = y;
    }
    d.records.push_back(rec);
  }
  if (summary) {
    summary->records = static_cast<std::size_t>(o.records);
    summary->samples = d.x.size();
    summary->steps = static_cast<std::size_t>(o.records) * ((n - 1) * o.substeps + burn_steps);
    summary->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  }
  return d;
}

}  // namespace vehs::sim

#pragma once
// Ensembles of records of the model SDE, sampled as a sensor would sample them.
#include <cstdint>
#include <string>
#include <vector>

#include "vehs/core/enum_names.hpp"
#include "vehs/core/model.hpp"
#include "vehs/io/measurements.hpp"

namespace vehs::sim {

enum class Scheme {
  EulerMaruyama,  ///< strong order 1 for this noise structure
  Rk4Euler,       ///< the paper's Eq. 30: RK4 on the drift + Euler noise on Y
  Baoab,          ///< BAOAB splitting (kick, drift, exact OU for linear damping, drift, kick)
  Taylor15,       ///< Kloeden–Platen strong order 1.5 Itô–Taylor scheme
};
inline constexpr EnumNames<Scheme, 4> kSchemeNames{{{Scheme::EulerMaruyama, "euler_maruyama"},
                                                     {Scheme::Rk4Euler, "rk4_euler"},
                                                     {Scheme::Baoab, "baoab"},
                                                     {Scheme::Taylor15, "taylor15"}}};

/// Initial displacement per record: uniform in [lo, hi] (the paper: [−1.5, 1.5]) or given
/// values (one per record). Initial velocity is y0 for every record.
struct InitialCondition {
  bool uniform = true;
  double lo = -1.5, hi = 1.5;
  std::vector<double> values;
  double y0 = 0.0;
};

struct SimulationOptions {
  double dt = 0.001;             ///< recorded sampling interval
  int substeps = 1;              ///< internal steps per recorded interval (h = dt / substeps)
  std::size_t samples = 100000;  ///< recorded samples per record (t = 0, dt, …)
  int records = 100;
  Scheme scheme = Scheme::Rk4Euler;
  std::uint64_t seed = 1;
  InitialCondition x0;
  double burn_in = 0.0;          ///< time simulated and discarded before the first sample
  double sensor_noise = 0.0;     ///< std. deviation of white noise added to the recorded x
  bool record_y = true;          ///< also store the true velocity (column y)
  /// Recorded drive u for models with a `u` term: one value per recorded sample (held
  /// constant over the substeps of an interval), shared by all records.
  std::vector<double> drive;
  bool progress = false;         ///< report progress on stderr

  /// Empty when valid, else a one-line reason.
  std::string invalid_reason() const;
};

struct SimulationSummary {
  std::size_t records = 0;
  std::size_t samples = 0;     ///< recorded samples in total
  std::size_t steps = 0;       ///< integration steps in total (incl. burn-in)
  double seconds = 0.0;
  int threads = 1;
};

/// Simulates `options.records` independent records. Results are identical whatever the thread
/// count. Throws vehs::Error naming the record and time when a record diverges.
Dataset simulate(const Model& model, const SimulationOptions& options,
                 SimulationSummary* summary = nullptr);

}  // namespace vehs::sim

#pragma once
// Ensembles of records of the model SDE (docs/model-file.md), sampled as a sensor samples them, and
// Monte Carlo statistics of ensembles or long runs.
//
// Time axis. A record has `samples` recorded values at t_i = i·dt, i = 0 … samples − 1 (so a
// record of "duration T" has samples = round(T / dt) values and ends at T − dt, as in the seed
// paper: Δt = 0.001, 10⁵ samples). Between two samples the SDE is integrated with `substeps`
// internal steps of h = dt / substeps (a sensor samples a continuous process). `burn_in` > 0
// first integrates over [−burn_in', 0) with burn_in' = round(burn_in / dt)·dt, unrecorded.
// The model's time (harmonic forcing) is the recorded t.
//
// Randomness. Philox-4x32-10 keyed by `seed`, counter = (index, record id, purpose) (see
// random.hpp): step n of record r uses normals [n·M, n·M + M) of its Dynamics stream (M = normals
// per step of the scheme), so a record is bit-identical whatever the thread count and however
// records are batched. Record ids are first_record … first_record + records − 1, so an ensemble
// can be extended (or split over machines) reproducibly.
//
// Initial state. x0 uniform in [lo, hi] (the paper: [−1.5, 1.5]) or given per record; y0 a
// constant, uniform or given per record; v(0) = 0; η(0) drawn from its stationary law
// N(0, intensity/(2τ)).
//
// Records that diverge (a non-finite state, or |x|, |y| above divergence_bound) stop the run
// with a vehs::Error naming the record and the time; nothing is written as NaN.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "vehs/core/dataset.hpp"
#include "vehs/core/enum_names.hpp"
#include "vehs/core/model.hpp"
#include "vehs/core/progress.hpp"
#include "vehs/core/statistics.hpp"
#include "vehs/sim/scheme.hpp"

namespace vehs::sim {

/// Initial displacement per record: uniform in [lo, hi] (the paper: [−1.5, 1.5]) or given
/// values (one per record). Initial velocity: y0 for every record, unless y_uniform (uniform in
/// [y_lo, y_hi]) or y_values (one per record) say otherwise.
struct InitialCondition {
  bool uniform = true;
  double lo = -1.5, hi = 1.5;
  std::vector<double> values;
  double y0 = 0.0;
  bool y_uniform = false;
  double y_lo = 0.0, y_hi = 0.0;
  std::vector<double> y_values;
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
  ProgressCallback progress;     ///< progress reports (task "simulate"); empty: none

  /// Alternative to `drive`: one drive series per record (same length rules).
  std::vector<std::vector<double>> drive_per_record;
  std::uint64_t first_record = 0;   ///< id of the first record (traj column, random stream)
  double divergence_bound = 1e8;    ///< |x| or |y| beyond this counts as divergence
  bool allow_unconfined = false;    ///< accept a potential that does not confine
  /// Largest output the simulator may allocate for the records (bytes); 0: 75 % of the RAM.
  double memory_limit = 0.0;

  /// Empty when valid, else a one-line reason.
  std::string invalid_reason() const;
};

struct SimulationSummary {
  std::size_t records = 0;
  std::size_t samples = 0;     ///< recorded samples in total
  std::size_t steps = 0;       ///< integration steps in total (incl. burn-in)
  double seconds = 0.0;
  int threads = 1;
  double steps_per_second = 0.0;
  double h = 0.0;              ///< internal step
  std::string scheme;
};

/// Checks a model and options before simulating: the options' invalid_reason(), validate_model,
/// a22 ≥ 0 over the region the records start in (and for large |x|), a confining potential
/// (leading power of the restoring force odd with a negative coefficient, or an impact stop,
/// unless allow_unconfined), drive presence and length. Throws a one-line vehs::Error
/// prefixed with `where`.
void check_simulation(const Model& model, const SimulationOptions& options,
                      const std::string& where = "simulation");

/// The memory check simulate() makes before allocating: the records `options` asks for (x; y
/// when record_y; the drive's copy u when `with_drive`) plus `extra_values` doubles a caller
/// builds for them (e.g. a drive refined to the internal steps), in bytes against
/// options.memory_limit. Throws simulate()'s one-line vehs::Error when over. Callers whose inputs
/// scale with the records (samples × substeps) call it before building them.
void check_memory(const SimulationOptions& options, bool with_drive, double extra_values = 0.0);

/// Simulates `options.records` independent records. Results are identical whatever the thread
/// count. Throws vehs::Error naming the record and time when a record diverges.
Dataset simulate(const Model& model, const SimulationOptions& options,
                 SimulationSummary* summary = nullptr);
/// The same into `out`, reusing its memory when the sizes match (repeated simulations avoid
/// re-allocating and re-touching hundreds of MB). On error `out` is left in a valid but
/// unspecified state.
void simulate(const Model& model, const SimulationOptions& options, Dataset& out,
              SimulationSummary* summary = nullptr);

// ---- Monte Carlo statistics ------------------------------------------------------------------

/// Which samples enter the statistics and how histograms are binned. Histogram grids follow
/// conventions.hpp: n cells over [min, max], cell i centred at min + (i + ½)·(max − min)/n —
/// the grid of fpk-stationary, so densities compare cell by cell.
struct StatisticsOptions {
  double discard = 0.0;        ///< time at the start of each record left out (transient)
  bool histograms = false;
  double x_min = -2.0, x_max = 2.0;
  std::size_t nx = 100;
  double y_min = -2.0, y_max = 2.0;
  std::size_t ny = 100;
  std::size_t batches = 32;    ///< contiguous batches per record for batch-means errors
  /// With at least this many records, standard errors come from the spread of the record
  /// means (independent records); with fewer, from the pooled batch means of all records
  /// (valid when a batch is much longer than the correlation time).
  int min_records_for_spread = 16;

  std::string invalid_reason() const;
};

struct MonteCarloStatistics {
  /// "E[X]", "E[Y]", "E[X^2]", "E[Y^2]", "E[XY]", "E[X^4]", and "E[V^2]" with
  /// electromechanical coupling; each a mean with its standard error.
  std::vector<std::pair<std::string, Estimate>> moments;
  /// record_means[k][r]: the mean of moment k (order of `moments`) over record r's used samples,
  /// for derived quantities with honest error bars (e.g. an energy-balance residual).
  std::vector<std::vector<double>> record_means;
  /// batch_means[k][r·B + b]: the mean of moment k over batch b of record r (B contiguous
  /// batches of the used samples, batch_lengths samples each, the same for every record): what
  /// merges blocks of records into the batch-means errors of a small ensemble (vehs.dask).
  std::vector<std::vector<double>> batch_means;
  std::vector<double> batch_lengths;
  Histogram1D px, py;
  Histogram2D pxy;
  bool has_histograms = false;
  std::size_t records = 0;
  std::size_t samples_per_record = 0;  ///< used samples per record (after discard)
  double discard = 0.0;
  std::string error_method;            ///< "independent records" or "batch means"

  const Estimate& moment(const std::string& name) const;  ///< throws when absent
};

/// Simulates and accumulates statistics while streaming (memory independent of the record
/// length). With `keep` non-null the records are also stored there (as simulate() would).
MonteCarloStatistics simulate_statistics(const Model& model, const SimulationOptions& options,
                                         const StatisticsOptions& statistics,
                                         SimulationSummary* summary = nullptr,
                                         Dataset* keep = nullptr);

/// The same statistics of stored records (needs the y column).
MonteCarloStatistics dataset_statistics(const Dataset& data, const StatisticsOptions& statistics);

}  // namespace vehs::sim

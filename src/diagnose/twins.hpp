#pragma once
// Twins (private): records simulated from the model, one per data record and replicate, with the
// record's duration, sampling interval, initial state, drive and measurement process.
#include <cstdint>
#include <vector>

#include "vehs/core/model.hpp"
#include "vehs/core/dataset.hpp"
#include "vehs/sim/simulate.hpp"

namespace vehs::diagnose::detail {

struct TwinSettings {
  sim::Scheme scheme = sim::Scheme::Rk4Euler;
  int substeps = 1;
  double sensor_noise = 0.0;
  std::uint64_t seed = 1;
  int smoothing = 1;  ///< half-width (samples) of the initial-state fit; > 1 with sensor noise
};

/// Initial displacement and velocity of every record: x[0] and the second-order one-sided
/// difference (−3x0 + 4x1 − x2)/(2Δt) for clean data; with smoothing w > 1 a least-squares
/// quadratic over the first 2w + 1 samples (sensor noise).
void initial_states(const Dataset& data, int smoothing, std::vector<double>& x0, std::vector<double>& y0);

class TwinSimulator {
 public:
  TwinSimulator(const Model& model, const Dataset& data, const TwinSettings& settings);
  /// Simulates replicate `rep` into `out` (records in the data's order, same sizes and t0).
  void simulate(int rep, Dataset& out);

 private:
  struct Group {
    std::vector<std::size_t> records;
    double t0 = 0.0;
    std::size_t samples = 0;
  };
  const Model& model_;
  const Dataset& data_;
  TwinSettings settings_;
  std::vector<double> x0_, y0_;
  std::vector<Group> groups_;
  bool harmonic_ = false;
  Dataset scratch_;
};

}  // namespace vehs::diagnose::detail

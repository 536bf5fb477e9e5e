#pragma once
// Consistency study (the seed paper's Table 4): for every grid point (Δt, N) simulate `repeats`
// independent datasets of `records` records of N samples from a known model, identify each,
// and report the mean and standard deviation of every physical parameter (β, k_i, 2D, 2Q, …),
// how often the selected support is exactly the true one, and how often the nominal 95 %
// intervals (±1.96 reported standard errors) cover the truth (a calibration check).
#include <cstdint>
#include <string>
#include <vector>

#include "vehs/core/model.hpp"
#include "vehs/core/progress.hpp"
#include "vehs/identify/identify.hpp"
#include "vehs/sim/simulate.hpp"

namespace vehs::identify {

struct StudyPoint {
  double dt = 0.001;            ///< recorded sampling interval
  std::size_t samples = 100000; ///< samples per record
};

struct StudyOptions {
  Model truth;
  std::vector<StudyPoint> points;
  int repeats = 10;
  int records = 10;
  sim::Scheme scheme = sim::Scheme::Rk4Euler;
  int substeps = 1;
  sim::InitialCondition x0;  ///< default uniform in [−1.5, 1.5] (the paper)
  std::uint64_t seed = 1;
  double sensor_noise = 0.0;
  double burn_in = 0.0;
  Options identify;          ///< estimator settings used for every dataset
  ProgressCallback progress;  ///< one event per (point, repeat); empty: none

  std::string invalid_reason() const;
};

struct StudyParameter {
  std::string name;      ///< physical name (beta, k3, 2D, ...)
  double truth = 0.0;
  double mean = 0.0, sd = 0.0;   ///< over repeats (0 when not selected)
  double mean_stderr = 0.0;      ///< mean reported standard error
  double coverage = 0.0;         ///< fraction of repeats with |est − truth| ≤ 1.96·se
};

struct StudyPointResult {
  StudyPoint point;
  std::vector<StudyParameter> parameters;
  double support_exact = 0.0;    ///< fraction of repeats with exactly the true terms
  std::vector<std::string> estimators_used;  ///< per repeat
  double seconds_identify = 0.0, seconds_simulate = 0.0;
};

struct StudyResult {
  std::vector<StudyPointResult> points;
  double coverage = 0.0;        ///< over all points, repeats and true parameters
  long long intervals = 0;      ///< number of (repeat, parameter) intervals behind `coverage`
};

StudyResult run_study(const StudyOptions& options);

}  // namespace vehs::identify

#pragma once
// Internal: the stages of a diagnosis and what they share. The comparison holds the lens, the
// units, the statistics setup (from the data only) and the per-unit statistics of the data and of
// the model's twins; every test reads it. diagnose() runs: sampling and lens → units → setup →
// statistics of data and twins → tests (one-step map, paired components with the model's
// parameter uncertainty, residual lines) → quantities and curves → FPK reference → suspects →
// verdict → confirmation of close contenders.
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "twins.hpp"
#include "vehs/core/record_phases.hpp"
#include "unit_stats.hpp"
#include "vehs/diagnose/diagnose.hpp"
#include "vehs/fpk/stationary.hpp"

namespace vehs::diagnose::detail {

/// Elapsed time per stage, appended to Result::timings.
class Stopwatch {
 public:
  void lap(Result& res, const char* stage) {
    const auto now = std::chrono::steady_clock::now();
    res.timings.emplace_back(stage, std::chrono::duration<double>(now - last_).count());
    last_ = now;
  }
  double total_seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now(), last_ = start_;
};

// ---- sampling and lens (sampling.cpp)

/// How the data were sampled (the twins are simulated accordingly) and the lens to look at them.
struct SamplingChoice {
  SamplingVerdict verdict = SamplingVerdict::ContinuousTime;
  Lens lens;
};
/// Reads the model's fit, runs the data's own sampling diagnosis, chooses the lens; fills
/// res.sampling, res.lens and warnings. Throws when the model was fitted at another interval.
SamplingChoice choose_sampling_and_lens(const Model& model, const Dataset& data, const Options& opt, Result& res);

// ---- units (units.cpp)

/// The units of the paired tests: records, or time blocks of them when there are fewer records
/// than Options::min_units.
struct UnitPlan {
  std::vector<UnitSpan> units;
  std::size_t per = 1;            ///< blocks per record
  std::size_t rows = 0;           ///< lens rows of all records
  std::size_t min_unit_len = 0;   ///< samples of the shortest unit
  std::size_t min_unit_rows = 0;  ///< lens rows of the shortest unit
  int count() const { return static_cast<int>(units.size()); }
};
/// Throws when the data are too few; fills res.rows, units, unit_kind and warnings.
UnitPlan plan_units(const Dataset& data, const Lens& lens, int min_units, Result& res);

// ---- the comparison (comparison.cpp, setup.cpp)

struct Comparison {
  Comparison(const Model& m, const Dataset& d, const Options& o, const Lens& l)
      : model(m), data(d), options(o), lens(l), model_lens(m, l), forcing_t0(forcing_time_origins(m, d, "diagnose", true)) {}
  Comparison(const Comparison&) = delete;
  Comparison& operator=(const Comparison&) = delete;

  const Model& model;
  const Dataset& data;
  const Options& options;
  Lens lens;
  ModelLens model_lens;
  /// Per record, the time at its first sample of the model's harmonic forcing: t0, shifted to
  /// the record's own phase when the model has one per record (vehs/core/record_phases.hpp).
  std::vector<double> forcing_t0;
  UnitPlan plan;
  StatsSetup setup;                       ///< setup.lens points to model_lens
  std::unique_ptr<fpk::FpkModel> fpk;     ///< the model's stationary FPK (null when it has none)
  TwinSettings twin_settings;
  int replicates = 1;
  std::vector<UnitStats> data_stats;      ///< per unit
  std::vector<UnitStats> twin_stats;      ///< per unit, summed over replicates
  std::vector<UnitStats> twin_rep0;       ///< per unit, replicate 0 (common random numbers of the draws)
  std::vector<std::vector<double>> rep_hx, rep_hxy;  ///< pooled histograms of replicates 0 and 1

  int units() const { return plan.count(); }
};

/// The statistics setup from a subsample of the data's rows (map and histogram ranges, coarse
/// cells, wells of the model's potential, spectrum and ACF sizes); checks that the model's
/// residual variance is positive where the data are.
void make_setup(Comparison& cmp, Result& res);

/// Per-unit statistics of the data and of `replicates` twins of every record; fills
/// res.sampling's twin settings and the warnings.
void compute_statistics(Comparison& cmp, SamplingVerdict verdict, Result& res, Stopwatch& watch);

// ---- tests (one_step_test.cpp, paired_tests.cpp, parameter_uncertainty.cpp, line_test.cpp)

/// The one-step map (residual mean and variance per (x, v̂) bin, paired jackknife) and its test.
Component one_step_test(const Comparison& cmp, OneStepMap& map);

/// A per-unit difference vector data − twins of one component (false when undefined for a unit).
using DiffFn = std::function<bool(const UnitStats&, const UnitStats&, Eigen::VectorXd&)>;
struct PairedStatistic {
  std::string name, what;
  DiffFn f;
  int p = 0;
  /// The model's parameter uncertainty moves it (stationary statistics, x spectrum, and the
  /// residual shapes: data residuals are whitened by fitted coefficients whose error and
  /// estimator bias the twins do not share).
  bool parameter_sensitive = false;
};
/// The components compared by Hotelling tests: residual shapes, residual spectrum, p(x, v̂)
/// cells, power, wells, spectrum of x.
std::vector<PairedStatistic> paired_statistics(const StatsSetup& setup, int units);
/// Rows f(A_j, B_j) of the units where f is defined.
Eigen::MatrixXd unit_differences(const DiffFn& f, const std::vector<UnitStats>& A, const std::vector<UnitStats>& B, int p);

/// The covariance the model's parameter uncertainty adds to each parameter-sensitive paired
/// statistic: refits on pseudo-data simulated from the model, resimulated with common random
/// numbers. Returns the number of draws (0: not used; res gets the warning when it failed).
int parameter_uncertainty(const Comparison& cmp, const std::vector<PairedStatistic>& paired,
                          std::vector<ExtraCovariance>& extra, Result& res);

/// The largest single-frequency excess of the residual spectrum (periodic forcing).
Component residual_line_test(const Comparison& cmp);

// ---- what the report shows (quantities.cpp, curves.cpp, fpk_reference.cpp)

/// E[X²], E[v̂²], well probabilities and the transition rate, data vs twins.
void add_quantities(const Comparison& cmp, Result& res);
/// p(x), p(x, v̂), residual and x ACFs and spectra with standard errors, Hellinger distances.
void add_curves(const Comparison& cmp, Result& res);
/// The model's stationary FPK density as a reference for p(x), E[X²] and E[Y²].
void add_fpk_reference(const Comparison& cmp, Result& res);

// ---- the comparison as a whole (diagnose.cpp), suspects and verdict (suspect_stage.cpp, verdict.cpp)

/// Everything but the suspects: the model against its twins.
Result compare_with_twins(const Model& model, const Dataset& data, const Options& opt, Stopwatch& watch);

/// Ranks the suspects (on whole records up to Options::suspect_samples) and adds their test;
/// returns the subset of the data they were fitted on when they did not use all of it.
std::optional<Dataset> add_suspects(const Model& model, const Dataset& data, const Options& opt, Result& res,
                                    Stopwatch& watch);

/// The likelihood's score tests of the effects the model lacks (score_suspects.hpp) and their
/// component: the smallest p-value, Bonferroni over the tested effects.
void add_score_suspects(const Model& model, const Dataset& data, const Options& opt, Result& res, Stopwatch& watch);

/// Verdict, score and threshold from the components (Bonferroni over the available ones).
void finish_verdict(Result& res, double alpha);

/// The confirmation of close contenders (suspects.hpp): colored_noise against the deterministic
/// dynamic forces, by refits and their comparisons with their twins.
void confirm_contenders(const Model& model, const Dataset& data, const Lens& lens, const Options& opt,
                        SuspectReport& rep);

/// The confirmation of the significant suspects by held-out refits (confirmation.hpp) into
/// res.confirmation; for an inadequate model with Options::confirm enabled.
void confirm_suspects(const Model& model, const Dataset& data, const Options& opt, Result& res, Stopwatch& watch);

/// res.recommended, res.outside_catalogue and res.conclusion from the verdict, the suspects and
/// the confirmation.
void conclude(Result& res, bool confirmed_by_refits);

}  // namespace vehs::diagnose::detail

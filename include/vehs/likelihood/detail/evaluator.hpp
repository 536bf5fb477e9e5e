#pragma once
// The likelihood of a data set as a function of θ (detail/parameterization.hpp): blocks, priors
// and substeps fixed once, then value (double) or value + derivatives (ceres::Jet) over all
// blocks in parallel, reduced in block order (results independent of the thread count).
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vehs/core/dataset.hpp"
#include "vehs/likelihood/detail/block_filter.hpp"
#include "vehs/likelihood/detail/parameterization.hpp"
#include "vehs/likelihood/filter.hpp"
#include "vehs/likelihood/filter_diverged.hpp"

namespace vehs::likelihood::detail {

struct Block {
  std::size_t record = 0;  ///< index into Dataset::records
  std::size_t first = 0;   ///< index of its first sample within the record
  BlockData data;
};

/// Where the filter failed, for a one-line error.
struct EvaluationFailure {
  bool failed = false;
  std::size_t record = 0, sample = 0;  ///< sample index within the record
  std::string what;
};

/// Value, gradient (internal scale) and, on request, the Fisher information of the innovations
/// Σ_k [∂e ∂eᵀ/S + ½ ∂S ∂Sᵀ/S²] and score sums over contiguous batches.
struct Derivatives {
  double log_likelihood = 0.0;
  Eigen::VectorXd gradient;
  Eigen::MatrixXd fisher;        ///< when requested
  Eigen::MatrixXd batch_scores;  ///< one row per batch, when requested
};

class Evaluator {
 public:
  Evaluator(const Parameterization& p, const Dataset& data, const FilterOptions& options,
            const std::string& where);

  const Parameterization& parameterization() const { return p_; }
  const Dataset& data() const { return data_; }
  const std::vector<Block>& blocks() const { return blocks_; }
  const FilterSettings& settings() const { return settings_; }
  std::size_t observations() const { return observations_; }
  int threads() const { return threads_; }
  /// Samples per batch of the score sums (sandwich); 0 means one batch per record.
  std::size_t batch_samples = 0;

  /// Log-likelihood at θ; false (with `failure`) when the filter fails.
  bool value(const double* theta, double& ll, EvaluationFailure* failure) const;
  /// Log-likelihood of every record at θ (per_record[r], r over Dataset::records).
  bool record_values(const double* theta, std::vector<double>& per_record, EvaluationFailure* failure) const;
  /// Value and gradient (and optionally Fisher information, batch scores).
  bool derivatives(const double* theta, Derivatives& out, bool fisher, bool batches,
                   EvaluationFailure* failure) const;
  /// The filter's trace at θ (FilterTrace of filter.hpp).
  bool trace(const double* theta, FilterTrace& out, EvaluationFailure* failure) const;

  /// Jet slots a block needs: the shared parameters and the record's phase.
  int slots() const { return int(p_.shared()) + (p_.local_phase() ? 1 : 0); }

  /// One-line message of a failure.
  std::string message(const EvaluationFailure& f) const;

 private:
  const Parameterization& p_;
  const Dataset& data_;
  std::vector<Block> blocks_;
  FilterSettings settings_;
  std::size_t observations_ = 0;
  int threads_ = 1;
  std::string where_;
};

/// Derivatives with Jets of N slots (instantiated for a few N in src/likelihood/jets_*.cpp).
template <int N>
bool evaluate_jets(const Evaluator& ev, const double* theta, Derivatives& out, bool fisher,
                   bool batches, EvaluationFailure* failure);

/// Jet sizes compiled; the smallest >= slots is used.
inline constexpr int kJetSizes[] = {4, 6, 8, 10, 12, 16, 24, 32};

/// The substeps rule of FilterOptions::substeps = 0 (exposed for tests).
int automatic_substeps(const Structure& st, const Coefficients<double>& c, const Dataset& data);

}  // namespace vehs::likelihood::detail

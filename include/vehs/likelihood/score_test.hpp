#pragma once
// The score (Lagrange-multiplier) test of a model against a larger one, from one filter pass
// with derivatives at the smaller model: does the data's likelihood rise when parameters ψ that
// the model holds at a null value (0: a friction coefficient, a stop stiffness, a coupling, an
// excitation intensity) are freed?
//
// With g = ∂log L/∂(θ, ψ) and F the Fisher information of the innovations (filter.hpp), both at
// the model, the efficient score and its information are
//     s = g_ψ − F_ψθ F_θθ⁻¹ g_θ,       V = F_ψψ − F_ψθ F_θθ⁻¹ F_θψ,
// and S = sᵀ V⁻¹ s is asymptotically χ² with dim ψ degrees of freedom under the model. This is
// Neyman's C(α) form: θ (the model's own free parameters) need only be √n-consistent — an
// identify fit, not necessarily the maximum of this likelihood — because the projection removes
// the first-order effect of θ's error. One step of Fisher scoring from the null gives the
// estimate ψ̂ = ψ₀ + V⁻¹ s with standard errors sqrt(diag V⁻¹); for one parameter the signed
// z = s/√V is the test (one-sided for parameters that are ≥ 0) and equals ψ̂/SE.
//
// The tested parameters must be free in `model` (non-zero drift or diffusion coefficients —
// use a tiny value such as 1e-300 for a null of 0 — or effect parameters, which may be exactly
// 0) and are kept on their natural scale. Nuisance parameters a larger model has but that are
// not identified under the null (a stop's gap, a coupling's λ, an excitation's τ, a forcing's
// ω) belong in `fixed`: the caller scans them and corrects for the scan.
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vehs/core/dataset.hpp"
#include "vehs/likelihood/filter.hpp"
#include "vehs/likelihood/observed_model.hpp"

namespace vehs::likelihood {

struct ScoreTestOptions {
  FilterOptions filter;
  /// The measurement noise is a nuisance parameter (when the model's measurement_sd > 0).
  bool estimate_measurement_noise = true;
  /// Parameter names held at their values (neither tested nor projected out).
  std::vector<std::string> fixed;
};

struct ScoreTestResult {
  std::vector<std::string> tested;
  std::vector<double> null_value;       ///< the tested parameters' values in the model
  Eigen::VectorXd efficient_score;      ///< s
  Eigen::MatrixXd efficient_information;  ///< V
  /// Per-record efficient scores (one row per record, columns as `tested`); their sum is s.
  Eigen::MatrixXd record_scores;
  double statistic = 0.0;  ///< sᵀ V⁻¹ s (pseudo-inverse over the identified directions)
  int dof = 0;             ///< rank of V
  double z = 0.0;          ///< one tested parameter: s/√V (signed); else 0
  std::vector<double> estimate, stderrs;  ///< one Fisher-scoring step from the null
  double log_likelihood = 0.0;
  std::size_t observations = 0;
  int substeps = 0;
};

/// Throws vehs::Error (one line) for a tested name that is not a free parameter of `model`, a
/// model or data the filter cannot take, or a filter that diverges.
ScoreTestResult score_test(const ObservedModel& model, const Dataset& data,
                           const std::vector<std::string>& tested,
                           const ScoreTestOptions& options = {});

/// Several independent tests from ONE derivative pass: each group of parameters is tested
/// against the model's own parameters with the other groups held at their null values (their
/// derivatives at the null are the same as in separate passes).
std::vector<ScoreTestResult> score_tests(const ObservedModel& model, const Dataset& data,
                                         const std::vector<std::vector<std::string>>& groups,
                                         const ScoreTestOptions& options = {});

}  // namespace vehs::likelihood

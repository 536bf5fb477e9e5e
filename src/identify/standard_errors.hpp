#pragma once
// Internal: standard errors of a term fit — the sandwich J⁻¹ Ω J⁻ᵀ of the stacked drift and
// diffusion estimating equations, Ω the covariance of their score sums over contiguous batches
// (batch means: robust to the correlated residuals of finite differences, heteroscedasticity and
// the dependence of the drift's Itô correction on the diffusion estimate).
#include <vector>

#include <Eigen/Dense>

#include "diffusion_pass.hpp"
#include "drift_pass.hpp"

namespace vehs::identify::detail {

/// What the sandwich needs from the passes of a fit.
struct ScoreSums {
  Eigen::MatrixXd kron;  ///< Σ_b vec(A_b) vec(A_b)ᵀ summed over the folds (diffusion_pass)
  double batches = 0.0;  ///< number of batches behind it
};
ScoreSums score_sums(const std::vector<DiffusionStats>& folds);

/// Standard errors of the drift coefficients on S and the diffusion coefficients on T (in that
/// order), at the final diffusion q (full ψ library) and sensor-noise variance s2. `drift_G` is the
/// corrected drift Gram matrix, `ito` the Itô moments Σ ψ ∂_vφ (used when `ito_correction`), and
/// `diffusion_G` the weighted diffusion Gram matrix. NaN where the variance is not positive.
/// `covariance`, when given, receives the whole sandwich (same order).
Eigen::VectorXd term_standard_errors(const ScoreSums& sums, const DiffusionSetup& ds, const Dictionary& phi, int P,
                                     const std::vector<int>& S, const std::vector<int>& T, const Eigen::VectorXd& q,
                                     double s2, const Eigen::MatrixXd& drift_G, const Eigen::MatrixXd& ito,
                                     bool ito_correction, const Eigen::MatrixXd& diffusion_G,
                                     Eigen::MatrixXd* covariance = nullptr);

}  // namespace vehs::identify::detail

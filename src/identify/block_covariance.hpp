#pragma once
// Internal: the covariance a model file carries when its estimates come from several fits (the
// dynamic-effect profile fit, the colored-noise GLS refit): one block per fit, each with its
// own correlations, the blocks uncorrelated with each other, every variance the square of the
// standard error written beside the estimate.
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "vehs/core/model.hpp"

namespace vehs::identify::detail {

struct CovarianceBlock {
  std::vector<std::string> names;  ///< model-file names: drift[t], diffusion[t], <effect>.<param>
  Eigen::MatrixXd cov;             ///< the fit's covariance of them (its correlations are kept)
  std::vector<double> stderr_;     ///< the standard errors written for them (the diagonal's roots)
};

/// D·R·D over all blocks: R block-diagonal of each block's correlation matrix, D the written
/// standard errors. Empty when a block is not positive definite or a standard error is not
/// positive and finite (the model then carries its standard errors only).
ParameterCovariance block_covariance(const std::vector<CovarianceBlock>& blocks);

}  // namespace vehs::identify::detail

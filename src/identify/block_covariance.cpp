#include "block_covariance.hpp"

#include <cmath>

namespace vehs::identify::detail {

ParameterCovariance block_covariance(const std::vector<CovarianceBlock>& blocks) {
  ParameterCovariance out;
  for (const auto& b : blocks) out.names.insert(out.names.end(), b.names.begin(), b.names.end());
  const std::size_t n = out.names.size();
  out.matrix.assign(n * n, 0.0);
  std::size_t at = 0;
  for (const auto& b : blocks) {
    const auto m = static_cast<Eigen::Index>(b.names.size());
    if (b.cov.rows() != m || b.cov.cols() != m || b.stderr_.size() != b.names.size()) return {};
    const Eigen::VectorXd sd = b.cov.diagonal().cwiseSqrt();
    for (Eigen::Index i = 0; i < m; ++i)
      if (!(sd[i] > 0.0 && std::isfinite(sd[i]) && b.stderr_[static_cast<std::size_t>(i)] > 0.0 &&
            std::isfinite(b.stderr_[static_cast<std::size_t>(i)])))
        return {};
    Eigen::MatrixXd r = sd.cwiseInverse().asDiagonal() * b.cov * sd.cwiseInverse().asDiagonal();
    r = 0.5 * (r + r.transpose());
    r.diagonal().setOnes();
    if (Eigen::LLT<Eigen::MatrixXd>(r).info() != Eigen::Success) return {};
    for (Eigen::Index i = 0; i < m; ++i)
      for (Eigen::Index j = 0; j < m; ++j)
        out(at + static_cast<std::size_t>(i), at + static_cast<std::size_t>(j)) =
            r(i, j) * b.stderr_[static_cast<std::size_t>(i)] * b.stderr_[static_cast<std::size_t>(j)];
    at += b.names.size();
  }
  return out;
}

}  // namespace vehs::identify::detail

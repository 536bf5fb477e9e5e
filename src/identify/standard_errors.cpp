#include "standard_errors.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vehs::identify::detail {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

/// Covariance of the batch sums of the stacked scores at (q, s²): Ω = Σ_b A_b q̃ q̃ᵀ A_bᵀ with
/// q̃ = [1; q; s²], from Σ_b vec(A_b) vec(A_b)ᵀ.
MatrixXd score_covariance(const MatrixXd& kron, int RS, const VectorXd& q, double s2) {
  const int CS = static_cast<int>(q.size()) + 2;
  VectorXd qt(CS);
  qt[0] = 1.0;
  qt.segment(1, q.size()) = q;
  qt[CS - 1] = s2;
  // s_b = Σ_k q̃_k A_b(:, k) = Q vec(A_b) with Q = q̃ᵀ ⊗ I
  MatrixXd Q = MatrixXd::Zero(RS, RS * CS);
  for (int k = 0; k < CS; ++k) Q.block(0, k * RS, RS, RS) = qt[k] * MatrixXd::Identity(RS, RS);
  return Q * kron * Q.transpose();
}

}  // namespace

ScoreSums score_sums(const std::vector<DiffusionStats>& folds) {
  ScoreSums s{folds[0].kron, folds[0].batches};
  for (std::size_t f = 1; f < folds.size(); ++f) {
    s.kron += folds[f].kron;
    s.batches += folds[f].batches;
  }
  return s;
}

VectorXd term_standard_errors(const ScoreSums& sums, const DiffusionSetup& ds, const Dictionary& phi, int P,
                              const std::vector<int>& S, const std::vector<int>& T, const VectorXd& q, double s2,
                              const MatrixXd& drift_G, const MatrixXd& ito, bool ito_correction,
                              const MatrixXd& diffusion_G, MatrixXd* covariance) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const MatrixXd omega_all = score_covariance(sums.kron, score_rows(ds, P), q, s2);
  const int p = static_cast<int>(S.size() + T.size());
  MatrixXd meat(p, p);
  {
    std::vector<int> rows;
    for (std::size_t i = 0; i < S.size(); ++i) rows.push_back(static_cast<int>(i));
    for (int t : T) rows.push_back(static_cast<int>(S.size()) + t);
    for (int i = 0; i < p; ++i)
      for (int j = 0; j < p; ++j) meat(i, j) = omega_all(rows[static_cast<std::size_t>(i)], rows[static_cast<std::size_t>(j)]);
  }
  // Jacobian of the stacked estimating equations (drift on S, diffusion on T)
  const int pS = static_cast<int>(S.size());
  MatrixXd J = MatrixXd::Zero(p, p);
  for (int i = 0; i < pS; ++i)
    for (int j = 0; j < pS; ++j) J(i, j) = drift_G(S[static_cast<std::size_t>(i)], S[static_cast<std::size_t>(j)]);
  if (ito_correction) {
    const auto& vt = phi.velocity_terms();
    for (int i = 0; i < pS; ++i) {
      const auto it = std::find(vt.begin(), vt.end(), S[static_cast<std::size_t>(i)]);
      if (it == vt.end()) continue;
      const Index col = static_cast<Index>(it - vt.begin());
      for (std::size_t t = 0; t < T.size(); ++t) J(i, pS + static_cast<int>(t)) = 0.5 * ito(T[t], col);
    }
  }
  for (std::size_t a = 0; a < T.size(); ++a)
    for (std::size_t b = 0; b < T.size(); ++b)
      J(pS + static_cast<int>(a), pS + static_cast<int>(b)) = diffusion_G(T[a], T[b]);
  VectorXd se = VectorXd::Constant(std::max(p, 1), kNaN);
  if (p > 0) {
    const MatrixXd Jinv = J.fullPivLu().inverse();
    const MatrixXd cov = Jinv * meat * Jinv.transpose();
    for (int i = 0; i < p; ++i) se[i] = cov(i, i) > 0 ? std::sqrt(cov(i, i)) : kNaN;
    if (covariance) *covariance = 0.5 * (cov + cov.transpose());
  }
  return se;
}

}  // namespace vehs::identify::detail

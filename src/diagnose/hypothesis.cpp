#include "vehs/diagnose/hypothesis.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Eigenvalues>

#include "vehs/diagnose/distributions.hpp"

namespace vehs::diagnose {

void finish_excess(TestResult& r) {
  r.excess = r.available && r.dof > 0 ? std::max(0.0, r.chi2 / r.dof - 1.0) : 0.0;
}

TestResult hotelling_zero_mean(const Eigen::MatrixXd& D, double rel_floor, const Eigen::MatrixXd* extra,
                               double extra_draws) {
  TestResult r;
  const auto U = static_cast<int>(D.rows());
  const auto p0 = static_cast<int>(D.cols());
  r.units = U;
  if (U < 3 || p0 < 1) {
    r.note = "too few units (" + std::to_string(U) + ") for a test";
    return r;
  }
  const Eigen::VectorXd mean = D.colwise().mean().transpose();
  const Eigen::MatrixXd C = D.rowwise() - mean.transpose();
  const Eigen::MatrixXd A = (C.transpose() * C) / (static_cast<double>(U - 1) * U);  // Cov of the mean
  Eigen::MatrixXd V = A;
  const bool with_extra = extra && extra->rows() == p0 && extra->cols() == p0 && extra_draws > 0;
  if (with_extra) V += *extra;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(V);
  const Eigen::VectorXd& lam = es.eigenvalues();
  const double lmax = lam.maxCoeff();
  if (!(lmax > 0.0)) {
    r.note = mean.norm() == 0.0 ? "data and twins agree exactly in every unit"
                                : "no unit-to-unit variation: the test is undefined";
    return r;
  }
  const Eigen::VectorXd proj = es.eigenvectors().transpose() * mean;
  double T2 = 0.0;
  int p = 0;
  for (int i = 0; i < p0; ++i)
    if (lam[i] > rel_floor * lmax) {
      T2 += proj[i] * proj[i] / lam[i];
      ++p;
    }
  // effective degrees of freedom of V on the kept subspace (Krishnamoorthy & Yu 2004, the
  // modified Nel–van der Merwe solution of the multivariate Behrens–Fisher problem): on the scale
  // where V is the identity, V = Ã + Ẽ, ν = (p + p²) / Σ_k [tr(M_k²) + (tr M_k)²]/ν_k
  double nu = U - 1.0;
  if (with_extra) {
    Eigen::MatrixXd Wh(p0, p);  // V^{-1/2} on the kept subspace
    int c = 0;
    for (int i = 0; i < p0; ++i)
      if (lam[i] > rel_floor * lmax) Wh.col(c++) = es.eigenvectors().col(i) / std::sqrt(lam[i]);
    const Eigen::MatrixXd At = Wh.transpose() * A * Wh, Et = Wh.transpose() * (*extra) * Wh;
    const double denom = ((At * At).trace() + At.trace() * At.trace()) / (U - 1.0) +
                         ((Et * Et).trace() + Et.trace() * Et.trace()) / extra_draws;
    nu = denom > 0 ? std::min(U - 1.0, (p + static_cast<double>(p) * p) / denom) : U - 1.0;
  }
  const double d2 = nu - p + 1.0;
  if (d2 < 1.0) {
    r.note = "too few degrees of freedom (" + std::to_string(nu) + ") for " + std::to_string(p) + " dimensions";
    return r;
  }
  const double F = T2 * d2 / (static_cast<double>(p) * nu);
  r.available = true;
  r.statistic = T2;
  r.dof = p;
  r.p_value = f_sf(F, p, d2);
  // for extreme misfits the large-sample χ² limit keeps the size finite and monotone
  r.chi2 = chi2_equivalent(r.p_value, p, F * p);
  std::ostringstream os;
  os << "paired Hotelling T2 = " << T2 << " on " << p << " dimensions over " << U << " units, F(" << p << ", "
     << d2 << ") = " << F;
  if (with_extra)
    os << "; covariance includes the model's parameter uncertainty (" << extra_draws
       << " refits), effective degrees of freedom " << nu;
  if (p < p0) os << " (" << p0 - p << " dimensions without variation dropped)";
  r.method = os.str();
  finish_excess(r);
  return r;
}

TestResult combine_t(const std::vector<double>& t, const std::vector<double>& nu) {
  TestResult r;
  double s = 0.0, raw = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (!std::isfinite(t[i]) || !(nu[i] >= 1.0)) continue;
    const double p = t_sf_two_sided(t[i], nu[i]);
    // χ²₁ equivalent; for underflowing p keep t² (the normal limit)
    s += p < 1e-290 ? t[i] * t[i] : chi2_isf(p, 1.0);
    raw += t[i] * t[i];
    ++n;
  }
  if (n == 0) {
    r.note = "no statistic with enough data";
    return r;
  }
  r.available = true;
  r.statistic = raw;
  r.chi2 = s;
  r.dof = n;
  r.p_value = chi2_sf(s, n);
  std::ostringstream os;
  os << "sum of " << n << " chi2(1) equivalents of paired-jackknife t statistics = " << s;
  r.method = os.str();
  finish_excess(r);
  return r;
}

}  // namespace vehs::diagnose

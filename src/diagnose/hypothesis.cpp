#include "vehs/diagnose/hypothesis.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <vector>

#include <Eigen/Eigenvalues>

#include "vehs/diagnose/distributions.hpp"

namespace vehs::diagnose {

void finish_excess(TestResult& r) {
  r.excess = r.available && r.dof > 0 ? std::max(0.0, r.chi2 / r.dof - 1.0) : 0.0;
}

namespace {

Eigen::MatrixXd clip_psd(const Eigen::MatrixXd& M) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(M);
  return es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).asDiagonal() * es.eigenvectors().transpose();
}

/// A square root L (L Lᵀ = S) of a positive semi-definite S.
Eigen::MatrixXd psd_root(const Eigen::MatrixXd& S) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(S);
  return es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
}

/// A draw of Wishart(k, L Lᵀ)/k (k a positive integer): Bartlett's decomposition for k well above
/// the dimension, else a sum of k outer products.
Eigen::MatrixXd wishart_mean_draw(const Eigen::MatrixXd& L, int k, std::mt19937_64& g) {
  const auto p = static_cast<int>(L.rows());
  std::normal_distribution<double> N;
  if (k <= 2 * p) {
    Eigen::MatrixXd Z(p, k);
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < p; ++i) Z(i, j) = N(g);
    const Eigen::MatrixXd LZ = L * Z;
    return LZ * LZ.transpose() / static_cast<double>(k);
  }
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(p, p);
  for (int i = 0; i < p; ++i) {
    std::chi_squared_distribution<double> c(static_cast<double>(k - i));
    T(i, i) = std::sqrt(c(g));
    for (int j = 0; j < i; ++j) T(i, j) = N(g);
  }
  const Eigen::MatrixXd LT = L * T;
  return LT * LT.transpose() / static_cast<double>(k);
}

/// mᵀ V⁺ m over the directions of V above rel·(largest eigenvalue).
double quadratic_form(const Eigen::MatrixXd& V, const Eigen::VectorXd& m, double rel) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(V);
  const Eigen::VectorXd pr = es.eigenvectors().transpose() * m;
  const double lmax = es.eigenvalues().maxCoeff();
  double t = 0.0;
  for (Eigen::Index i = 0; i < m.size(); ++i)
    if (es.eigenvalues()[i] > rel * lmax) t += pr[i] * pr[i] / es.eigenvalues()[i];
  return t;
}

/// ν of the F reference whose quantile at level q equals the simulated T² quantile `tq`.
double nu_matching_quantile(double tq, int p, double q) {
  auto sf_at = [&](double nu) {
    const double d2 = nu - p + 1.0;
    return f_sf(tq * d2 / (p * nu), p, d2);
  };
  double lo = p - 1.0 + 0.05, hi = 1e7;  // the upper tail at tq shrinks as ν grows
  if (sf_at(hi) >= 1.0 - q) return hi;
  if (sf_at(lo) <= 1.0 - q) return lo;
  for (int it = 0; it < 80; ++it) {
    const double mid = std::sqrt(lo * hi);
    (sf_at(mid) > 1.0 - q ? lo : hi) = mid;
  }
  return std::sqrt(lo * hi);
}

constexpr int kCalibrationDraws = 1000;
constexpr double kCalibrationLevel = 0.95;

}  // namespace

Eigen::MatrixXd ExtraCovariance::estimate() const { return clip_psd(second_moment - within); }

ExtraCovariance ExtraCovariance::scaled(double factor) const {
  ExtraCovariance e = *this;
  e.second_moment *= factor;
  e.within *= factor;
  return e;
}

TestResult hotelling_zero_mean(const Eigen::MatrixXd& D, double rel_floor, const ExtraCovariance* extra) {
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
  const bool with_extra = extra && extra->valid(p0);
  Eigen::MatrixXd E;
  if (with_extra) {
    E = extra->estimate();
    V += E;
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(V);
  const Eigen::VectorXd& lam = es.eigenvalues();
  const double lmax = lam.maxCoeff();
  if (!(lmax > 0.0)) {
    r.note = mean.norm() == 0.0 ? "data and twins agree exactly in every unit"
                                : "no unit-to-unit variation: the test is undefined";
    return r;
  }
  int p = 0;
  for (int i = 0; i < p0; ++i) p += lam[i] > rel_floor * lmax;
  Eigen::MatrixXd P(p0, p);  // orthonormal basis of the kept directions
  {
    int c = 0;
    for (int i = 0; i < p0; ++i)
      if (lam[i] > rel_floor * lmax) P.col(c++) = es.eigenvectors().col(i);
  }
  const Eigen::VectorXd mk = P.transpose() * mean;
  double T2 = 0.0;
  {
    int c = 0;
    for (int i = 0; i < p0; ++i)
      if (lam[i] > rel_floor * lmax) {
        T2 += mk[c] * mk[c] / lam[i];
        ++c;
      }
  }
  double nu = U - 1.0;
  if (with_extra) {
    // calibrate ν by simulating the estimation of V at the plug-in values (see the header)
    const Eigen::MatrixXd Ak = P.transpose() * A * P, Ek = P.transpose() * E * P,
                          Wk = P.transpose() * extra->within * P;
    const Eigen::MatrixXd LV = psd_root(Ak + Ek), LA = psd_root(Ak), LS = psd_root(Ek + Wk), LW = psd_root(Wk);
    const int B = std::max(1, static_cast<int>(std::lround(extra->draws)));
    const int kW = std::max(1, static_cast<int>(std::lround(extra->draws * std::max(1.0, extra->units - 1.0))));
    std::mt19937_64 g(0x7E57CA11B8A7Eull);
    std::normal_distribution<double> N;
    std::vector<double> t(kCalibrationDraws);
    for (int s = 0; s < kCalibrationDraws; ++s) {
      Eigen::VectorXd z(p);
      for (int k = 0; k < p; ++k) z[k] = N(g);
      const Eigen::VectorXd m = LV * z;
      const Eigen::MatrixXd As = wishart_mean_draw(LA, U - 1, g);
      const Eigen::MatrixXd Ss = wishart_mean_draw(LS, B, g);
      const Eigen::MatrixXd Ws = wishart_mean_draw(LW, kW, g);
      t[static_cast<std::size_t>(s)] = quadratic_form(As + clip_psd(Ss - Ws), m, rel_floor);
    }
    const auto qi = static_cast<std::size_t>(kCalibrationLevel * kCalibrationDraws);
    std::nth_element(t.begin(), t.begin() + static_cast<std::ptrdiff_t>(qi), t.end());
    nu = nu_matching_quantile(t[qi], p, kCalibrationLevel);
  }
  const double d2 = nu - p + 1.0;
  if (d2 < 1.0 && !with_extra) {
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
    os << "; covariance includes the model's parameter uncertainty (" << extra->draws
       << " refits), effective degrees of freedom " << nu << " (calibrated by simulation)";
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

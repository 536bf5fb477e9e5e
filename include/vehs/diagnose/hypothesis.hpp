#pragma once
// The calibrated tests behind the verdict of diagnose-vehs.
//
// Every comparison is PAIRED over units: a unit is an independent record (or, with fewer records
// than Options::min_units, a contiguous time block of one), and every unit of the data has twins —
// records simulated from the model with the unit's initial state, duration, sampling and drive.
// For a per-unit statistic vector s_j, d_j = s_j(data) − mean over twins s_j(twin) has mean zero
// under the model whatever the transient, estimator bias or non-stationarity, because data and
// twins pass through the same code. Two tests are used:
//  * hotelling_zero_mean — one-sample Hotelling T² of the d_j (few, correlated quantities:
//    coarse density cells, moments, well occupancies, band-averaged log spectra). With U units and
//    p dimensions, F = T²(U − p)/(p(U − 1)) ~ F(p, U − p) under the null (exact for Gaussian d_j);
//    directions with negligible variance (e.g. no well transitions anywhere) are dropped.
//  * combine_t — many nearly independent statistics each with a t reference (the one-step map:
//    residual mean and variance per phase-space bin, standard errors by the paired jackknife over
//    units): each two-sided t p-value is turned into its χ²₁ equivalent and the sum is referred to
//    χ²_B, B the number of bins used.
// The size of a misfit is the excess normalised chi-square max(0, χ²/dof − 1), where χ² is the
// χ²_dof quantile of the test's p-value (≈ 0 for an adequate model; grows with the misfit and
// with the amount of data).
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace vehs::diagnose {

struct TestResult {
  bool available = false;
  std::string note;       ///< why unavailable, or caveats
  std::string method;     ///< one line
  double statistic = 0.0; ///< T² or Σ χ²₁-equivalents
  double chi2 = 0.0;      ///< χ²_dof equivalent of the p-value
  double dof = 0.0;
  double p_value = 1.0;
  double excess = 0.0;    ///< max(0, chi2/dof − 1)
  int units = 0;
};

/// One-sample Hotelling T² test that the rows of D (U units × p) have mean zero. Directions whose
/// variance is below `rel_floor`·(largest eigenvalue) are dropped from the test.
///
/// `extra` (optional, p × p) is an additional covariance of the MEAN that the unit-to-unit spread
/// cannot show — the model-side parameter uncertainty, common to all units — estimated from
/// `extra_draws` independent draws. The test then uses V = S/U + extra, whose parts are known to
/// different degrees of freedom; the reference is F = T²(ν − p + 1)/(p ν) ~ F(p, ν − p + 1) with the
/// effective ν of Krishnamoorthy & Yu (2004; the modified Nel–van der Merwe solution of the
/// multivariate Behrens–Fisher problem) computed where V is the identity:
/// ν = (p + p²) / ([tr Ã² + (tr Ã)²]/(U − 1) + [tr Ẽ² + (tr Ẽ)²]/extra_draws), capped at U − 1.
/// Without `extra`, ν = U − 1 and the law is Hotelling's exact one.
TestResult hotelling_zero_mean(const Eigen::MatrixXd& D, double rel_floor = 1e-9,
                               const Eigen::MatrixXd* extra = nullptr, double extra_draws = 0.0);

/// Sum of χ²₁ equivalents of t statistics t[i] with nu[i] degrees of freedom (two-sided).
TestResult combine_t(const std::vector<double>& t, const std::vector<double>& nu);

/// Fills excess from chi2/dof.
void finish_excess(TestResult& r);

}  // namespace vehs::diagnose

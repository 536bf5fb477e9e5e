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

/// An additional covariance of the MEAN that the unit-to-unit spread cannot show — the model-side
/// parameter uncertainty, common to all units — estimated from `draws` independent draws e_b
/// (each the unit mean of one draw's differences) as  Ê = (1/B) Σ_b (e_b e_bᵀ − Ŵ_b),  Ŵ_b the
/// draw's own covariance of the mean (unit spread / units), which is subtracted.
struct ExtraCovariance {
  Eigen::MatrixXd second_moment;  ///< (1/B) Σ e_b e_bᵀ
  Eigen::MatrixXd within;         ///< (1/B) Σ Ŵ_b
  double draws = 0.0;             ///< B
  double units = 0.0;             ///< units behind each Ŵ_b (their dof is units − 1)
  bool valid(Eigen::Index p) const {
    return draws >= 1.0 && second_moment.rows() == p && second_moment.cols() == p && within.rows() == p &&
           within.cols() == p;
  }
  /// Ê with negative eigenvalues clipped to zero.
  Eigen::MatrixXd estimate() const;
  /// Same, scaled by `factor` (e.g. draws on fewer samples than the data).
  ExtraCovariance scaled(double factor) const;
};

/// One-sample Hotelling T² test that the rows of D (U units × p) have mean zero. Directions whose
/// variance is below `rel_floor`·(largest eigenvalue) are dropped from the test.
///
/// With `extra`, the test uses V = S/U + Ê (S the unit covariance, Ê = extra->estimate()), whose
/// parts are known to very different degrees of freedom (U − 1 for S; only B draws, partly
/// cancelled by the subtraction of Ŵ, for Ê). The reference is F = T²(ν − p + 1)/(p ν) ~
/// F(p, ν − p + 1), Hotelling's law with an effective ν, and ν is CALIBRATED by a parametric
/// simulation of the whole estimation at the plug-in values: m ~ N(0, V), S/U ~ Wishart(U − 1),
/// the draws' second moment ~ Wishart(B, Ê + Ŵ)/B, Ŵ ~ Wishart(B(U − 1))/(B(U − 1)), Ê clipped as
/// above; ν is chosen so that the F reference has the simulated 95 % quantile of T². (The
/// moment-matching ν of Krishnamoorthy & Yu assumes Ê is Wishart with B dof and ignores Ŵ and the
/// clipping: with B = 8 it rejects 8 % at a nominal 5 %.) The simulation uses a fixed seed, so
/// results are reproducible. Without `extra`, ν = U − 1 and the law is Hotelling's exact one.
TestResult hotelling_zero_mean(const Eigen::MatrixXd& D, double rel_floor = 1e-9,
                               const ExtraCovariance* extra = nullptr);

/// Sum of χ²₁ equivalents of t statistics t[i] with nu[i] degrees of freedom (two-sided).
TestResult combine_t(const std::vector<double>& t, const std::vector<double>& nu);

/// Fills excess from chi2/dof.
void finish_excess(TestResult& r);

}  // namespace vehs::diagnose

#pragma once
// Tail probabilities of the reference distributions behind the tests of diagnose-vehs:
// standard normal, Student t, chi-square and F. Implemented from the regularized incomplete
// gamma and beta functions (series and continued fractions, relative accuracy ~1e-12 in the
// range used here); checked against closed forms and tabulated quantiles in
// tests/diagnose/test_distributions.cpp.
namespace vehs::diagnose {

/// Φ(z) and the upper tail 1 − Φ(z) (accurate far in the tail, via erfc).
double normal_cdf(double z);
double normal_sf(double z);
/// z with normal_sf(z) = p, for p in (0, 1).
double normal_isf(double p);

/// Regularized lower incomplete gamma P(a, x) and its complement Q(a, x) = 1 − P(a, x).
double gamma_p(double a, double x);
double gamma_q(double a, double x);
/// Regularized incomplete beta I_x(a, b).
double beta_i(double a, double b, double x);

/// P(χ²_k > x).
double chi2_sf(double x, double k);
/// log P(χ²_k > x), also where P underflows (the incomplete gamma's continued fraction in logs).
double log_chi2_sf(double x, double k);
/// x with chi2_sf(x, k) = p (p in (0, 1]); for p below ~1e-300 it returns +inf.
double chi2_isf(double p, double k);
/// P(F(d1, d2) > f).
double f_sf(double f, double d1, double d2);
/// Two-sided P(|t_ν| > |t|); ν = inf gives the normal limit.
double t_sf_two_sided(double t, double nu);

/// The chi-square-equivalent of a statistic with upper-tail p-value p on k degrees of freedom:
/// chi2_isf(p, k), or `fallback` when p underflows (p < 1e-290), so extreme misfits keep a
/// finite, monotone size.
double chi2_equivalent(double p, double k, double fallback);

}  // namespace vehs::diagnose

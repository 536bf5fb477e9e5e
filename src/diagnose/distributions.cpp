#include "vehs/diagnose/distributions.hpp"

#include <cmath>
#include <limits>

namespace vehs::diagnose {

namespace {

constexpr double kEps = 1e-15;
constexpr double kTiny = 1e-300;
constexpr int kMaxIter = 100000;

/// Series of P(a, x), valid (fast) for x < a + 1.
double gamma_p_series(double a, double x) {
  double term = 1.0 / a, sum = term;
  for (int n = 1; n < kMaxIter; ++n) {
    term *= x / (a + n);
    sum += term;
    if (std::abs(term) < std::abs(sum) * kEps) break;
  }
  return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

/// log Q(a, x) by its continued fraction (modified Lentz), valid for x >= a + 1.
double log_gamma_q_fraction(double a, double x) {
  double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
  for (int i = 1; i < kMaxIter; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < kEps) break;
  }
  return -x + a * std::log(x) - std::lgamma(a) + std::log(h);
}

double gamma_q_fraction(double a, double x) { return std::exp(log_gamma_q_fraction(a, x)); }

/// Continued fraction of the incomplete beta function (modified Lentz).
double beta_fraction(double a, double b, double x) {
  const double qab = a + b, qap = a + 1.0, qam = a - 1.0;
  double c = 1.0, d = 1.0 - qab * x / qap;
  if (std::abs(d) < kTiny) d = kTiny;
  d = 1.0 / d;
  double h = d;
  for (int m = 1; m < kMaxIter; ++m) {
    const int m2 = 2 * m;
    double aa = m * (b - m) * x / ((qam + m2) * (a + m2));
    d = 1.0 + aa * d;
    if (std::abs(d) < kTiny) d = kTiny;
    c = 1.0 + aa / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    h *= d * c;
    aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
    d = 1.0 + aa * d;
    if (std::abs(d) < kTiny) d = kTiny;
    c = 1.0 + aa / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < kEps) break;
  }
  return h;
}

}  // namespace

double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }
double normal_sf(double z) { return 0.5 * std::erfc(z / std::sqrt(2.0)); }

double normal_isf(double p) {
  if (!(p > 0.0)) return std::numeric_limits<double>::infinity();
  if (!(p < 1.0)) return -std::numeric_limits<double>::infinity();
  // bracket, then bisection refined by Newton steps on log sf
  double lo = -40.0, hi = 40.0;
  for (int i = 0; i < 200 && hi - lo > 1e-14 * (1.0 + std::abs(lo)); ++i) {
    const double mid = 0.5 * (lo + hi);
    if (normal_sf(mid) > p)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

double gamma_p(double a, double x) {
  if (!(x > 0.0)) return 0.0;
  if (std::isinf(x)) return 1.0;
  return x < a + 1.0 ? gamma_p_series(a, x) : 1.0 - gamma_q_fraction(a, x);
}

double gamma_q(double a, double x) {
  if (!(x > 0.0)) return 1.0;
  if (std::isinf(x)) return 0.0;
  return x < a + 1.0 ? 1.0 - gamma_p_series(a, x) : gamma_q_fraction(a, x);
}

double beta_i(double a, double b, double x) {
  if (!(x > 0.0)) return 0.0;
  if (!(x < 1.0)) return 1.0;
  const double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) +
                                a * std::log(x) + b * std::log1p(-x));
  if (x < (a + 1.0) / (a + b + 2.0)) return front * beta_fraction(a, b, x) / a;
  return 1.0 - front * beta_fraction(b, a, 1.0 - x) / b;
}

double chi2_sf(double x, double k) { return gamma_q(0.5 * k, 0.5 * x); }

double log_chi2_sf(double x, double k) {
  const double p = chi2_sf(x, k);
  if (p > 1e-280 || 0.5 * x < 0.5 * k + 1.0) return std::log(p);
  return log_gamma_q_fraction(0.5 * k, 0.5 * x);
}

double chi2_isf(double p, double k) {
  if (!(p < 1.0)) return 0.0;
  if (!(p > 1e-300)) return std::numeric_limits<double>::infinity();
  double lo = 0.0, hi = std::max(1.0, k);
  while (chi2_sf(hi, k) > p) {
    lo = hi;
    hi *= 2.0;
    if (hi > 1e12) return hi;
  }
  for (int i = 0; i < 300 && hi - lo > 1e-13 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (chi2_sf(mid, k) > p)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

double f_sf(double f, double d1, double d2) {
  if (!(f > 0.0)) return 1.0;
  if (std::isinf(f)) return 0.0;
  return beta_i(0.5 * d2, 0.5 * d1, d2 / (d2 + d1 * f));
}

double t_sf_two_sided(double t, double nu) {
  if (std::isinf(nu)) return 2.0 * normal_sf(std::abs(t));
  if (std::isinf(t)) return 0.0;
  return beta_i(0.5 * nu, 0.5, nu / (nu + t * t));
}

double chi2_equivalent(double p, double k, double fallback) {
  if (p < 1e-290) return std::max(fallback, chi2_isf(1e-290, k));
  return chi2_isf(p, k);
}

}  // namespace vehs::diagnose

#pragma once
// The statistical checks of the suite (COMMON.md): each states its false-failure probability per
// run — the probability, over the random draw its seed stands for, that correct code fails it —
// and that probability is at most kFalseFailure = 1e-4 per test case. The helpers turn the
// budget into thresholds from the test statistic's own distribution:
//  * z_bound(k):      k two-sided checks of N(0, 1) statistics (estimate − truth)/SE, Bonferroni:
//                     each |z| ≤ Φ⁻¹(1 − p/(2k)) (k = 1: 3.89, 2: 4.06, 4: 4.24, 8: 4.42,
//                     16: 4.59, 32: 4.75);
//  * t_bound(k, ν):   the same when the SE is estimated from ν + 1 independent units (Student t);
//  * binomial_floor(n, q): the smallest count a run may show of n independent events of
//                     probability q each (coverage of intervals, seeds passing a verdict);
//  * ks_bound():      √n·D of the Kolmogorov–Smirnov statistic, asymptotic distribution.
// Statistics whose error bars are only approximately calibrated (sandwich standard errors of
// identify, batch means) are checked with these bounds scaled by the spread of z measured over
// independent seeds (scripts/seed-study.sh), as the tests' comments say.
//
// Seed studies: seed(s) returns s + 1000003·VEHS_TEST_SEED_SHIFT (the environment variable;
// unset: s), and tally() appends "test<TAB>quantity<TAB>z<TAB>relative error" lines to the file
// named by VEHS_TEST_TALLY (unset: nothing). scripts/seed-study.sh N BINARY [TEST-SPEC] reruns
// tests on N shifted seeds and reports the mean and spread of every tallied z, so a threshold's
// false-failure probability and a bias check's real size rest on measurements, not on one seed.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <string>

#include "vehs/diagnose/distributions.hpp"

namespace vehs_test {

inline constexpr double kFalseFailure = 1e-4;

/// |z| bound of each of k two-sided checks of N(0, 1) statistics, family-wise probability p.
inline double z_bound(int k, double p = kFalseFailure) {
  return vehs::diagnose::normal_isf(p / (2.0 * k));
}

/// |t| bound of each of k two-sided checks of Student-t statistics with ν degrees of freedom.
inline double t_bound(int k, double nu, double p = kFalseFailure) {
  const double target = p / k;
  double lo = 0.0, hi = 1e3;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (vehs::diagnose::t_sf_two_sided(mid, nu) > target ? lo : hi) = mid;
  }
  return hi;
}

/// P(Bin(n, q) < m).
inline double binomial_below(int m, int n, double q) {
  double s = 0.0;
  for (int j = 0; j < m && j <= n; ++j)
    s += std::exp(std::lgamma(n + 1.0) - std::lgamma(j + 1.0) - std::lgamma(n - j + 1.0) +
                  j * std::log(q) + (n - j) * std::log1p(-q));
  return s;
}

/// The largest m with P(Bin(n, q) < m) ≤ p: a run of n events of probability q each shows
/// fewer than m with probability at most p.
inline int binomial_floor(int n, double q, double p = kFalseFailure) {
  int m = 0;
  while (m < n && binomial_below(m + 1, n, q) <= p) ++m;
  return m;
}

/// A count of n independent events of probability q each lies in [lo, hi] with probability at
/// least 1 − p (each tail ≤ p/2).
inline bool binomial_within(int count, int n, double q, double p = kFalseFailure) {
  const int lo = binomial_floor(n, q, p / 2), hi = n - binomial_floor(n, 1.0 - q, p / 2);
  return count >= lo && count <= hi;
}

/// x with P(√n·D > x) = p for the Kolmogorov distribution, P(K > x) = 2 Σ_j (−1)^{j−1} e^{−2j²x²}.
inline double ks_bound(double p = kFalseFailure) {
  auto sf = [](double x) {
    double s = 0.0;
    for (int j = 1; j <= 100; ++j) s += 2.0 * ((j % 2) ? 1.0 : -1.0) * std::exp(-2.0 * j * j * x * x);
    return s;
  };
  double lo = 0.3, hi = 10.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (sf(mid) > p ? lo : hi) = mid;
  }
  return hi;
}

/// The seed of a test, shifted by VEHS_TEST_SEED_SHIFT for seed studies.
inline std::uint64_t seed(std::uint64_t s) {
  const char* shift = std::getenv("VEHS_TEST_SEED_SHIFT");
  return s + (shift ? 1000003ull * std::strtoull(shift, nullptr, 10) : 0ull);
}

/// Records a statistic of the running test for scripts/seed-study.sh (no-op unless
/// VEHS_TEST_TALLY names a file): z = (estimate − truth)/SE, or any other value; rel the
/// relative error (NaN when not meaningful).
inline void tally(const std::string& quantity, double z,
                  double rel = std::numeric_limits<double>::quiet_NaN()) {
  const char* path = std::getenv("VEHS_TEST_TALLY");
  if (!path) return;
  std::ofstream f(path, std::ios::app);
  f.precision(10);
  f << Catch::getResultCapture().getCurrentTestName() << '\t' << quantity << '\t' << z << '\t';
  if (std::isfinite(rel))
    f << rel << '\n';
  else
    f << "nan\n";
}

}  // namespace vehs_test

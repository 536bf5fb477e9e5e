// Reference distributions against closed forms and tabulated quantiles.
#include <catch2/catch.hpp>

#include <cmath>

#include "vehs/diagnose/distributions.hpp"

using namespace vehs::diagnose;

TEST_CASE("normal tail and its inverse match tabulated quantiles", "[distributions]") {
  CHECK(normal_sf(1.959963984540054) == Approx(0.025).epsilon(1e-10));
  CHECK(normal_isf(0.025) == Approx(1.959963984540054).epsilon(1e-10));
  CHECK(normal_isf(1e-10) == Approx(6.361340902404056).epsilon(1e-9));
  CHECK(normal_cdf(0.0) == Approx(0.5));
}

TEST_CASE("chi-square tails: closed forms for 2 dof, tabulated quantiles, inverse round trip", "[distributions]") {
  for (double x : {0.1, 1.0, 5.0, 30.0, 200.0}) CHECK(chi2_sf(x, 2.0) == Approx(std::exp(-x / 2)).epsilon(1e-12));
  // P(χ²_1 > x) = erfc(sqrt(x/2))
  for (double x : {0.01, 0.5, 3.841458820694124, 20.0})
    CHECK(chi2_sf(x, 1.0) == Approx(std::erfc(std::sqrt(x / 2))).epsilon(1e-11));
  CHECK(chi2_sf(18.307038053275146, 10.0) == Approx(0.05).epsilon(1e-9));
  CHECK(chi2_sf(124.34211340400407, 100.0) == Approx(0.05).epsilon(1e-8));
  for (double k : {1.0, 3.0, 17.0, 500.0})
    for (double p : {0.5, 0.01, 1e-6, 1e-50}) CHECK(chi2_sf(chi2_isf(p, k), k) == Approx(p).epsilon(1e-8));
  CHECK(gamma_p(2.5, 1.7) + gamma_q(2.5, 1.7) == Approx(1.0).epsilon(1e-14));
  CHECK(std::isinf(chi2_isf(1e-320, 3.0)));
  CHECK(chi2_equivalent(1e-320, 3.0, 5000.0) >= 5000.0);
}

TEST_CASE("chi-square log tails far beyond underflow: closed forms for 2 and 4 dof, continuity", "[distributions]") {
  // log P(χ²_2 > x) = −x/2 and log P(χ²_4 > x) = −x/2 + log(1 + x/2) exactly; the normal
  // (Wilson–Hilferty) tail used before gave −337 for −870 at 2 dof
  for (double x : {10.0, 1500.0, 1740.0, 1e5}) {
    CHECK(log_chi2_sf(x, 2.0) == Approx(-x / 2).epsilon(1e-12));
    CHECK(log_chi2_sf(x, 4.0) == Approx(-x / 2 + std::log1p(x / 2)).epsilon(1e-12));
  }
  // continuous where chi2_sf underflows (p 1e-280) for many degrees of freedom
  const double x0 = chi2_isf(1e-279, 256.0);
  CHECK(log_chi2_sf(x0 * 1.0001, 256.0) < log_chi2_sf(x0, 256.0));
  CHECK(log_chi2_sf(x0 * 1.0001, 256.0) == Approx(std::log(chi2_sf(x0 * 1.0001, 256.0))).epsilon(1e-9));
  CHECK(log_chi2_sf(2000.0, 256.0) < log_chi2_sf(1900.0, 256.0));
}

TEST_CASE("Student t and F tails match tabulated quantiles and limits", "[distributions]") {
  CHECK(t_sf_two_sided(2.2281388519649385, 10.0) == Approx(0.05).epsilon(1e-9));
  CHECK(t_sf_two_sided(12.706204736174706, 1.0) == Approx(0.05).epsilon(1e-9));
  CHECK(t_sf_two_sided(1.96, 1e9) == Approx(2.0 * normal_sf(1.96)).epsilon(1e-6));
  CHECK(f_sf(4.102821015130399, 2.0, 10.0) == Approx(0.05).epsilon(1e-9));
  CHECK(f_sf(2.0, 1.0, 30.0) == Approx(t_sf_two_sided(std::sqrt(2.0), 30.0)).epsilon(1e-12));  // F(1,ν) = t²
  // F(p, ∞)·p → χ²_p
  CHECK(f_sf(3.0, 4.0, 1e8) == Approx(chi2_sf(12.0, 4.0)).epsilon(1e-5));
  CHECK(beta_i(2.0, 3.0, 0.4) == Approx(0.5248).epsilon(1e-12));  // closed form of I_0.4(2, 3)
}

// The Gaussian expectations of the filter's time update against direct numerical integration
// over the Gaussian density (a fine midpoint rule over ±12 standard deviations): moments of a
// correlated bivariate Gaussian, sign, y|y|, |y| and the hinges of end stops.
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <utility>

#include "vehs/likelihood/detail/gaussian_expectations.hpp"

using namespace vehs::likelihood::detail;

namespace {

/// E[f(x)] for x ~ N(m, s²), midpoint rule on each side of the kink or jump at `at`.
double integrate_1d(double m, double s, const std::function<double(double)>& f, double at) {
  const double lo = m - 12 * s, hi = m + 12 * s;
  const double cut = std::min(std::max(at, lo), hi);
  double sum = 0.0;
  for (const auto& [a, b] : {std::pair{lo, cut}, std::pair{cut, hi}}) {
    const int n = 100000;
    const double h = (b - a) / n;
    for (int i = 0; i < n; ++i) {
      const double x = a + (i + 0.5) * h, d = (x - m) / s;
      sum += h * f(x) * std::exp(-0.5 * d * d);
    }
  }
  return sum / (s * std::sqrt(2.0 * M_PI));
}

/// E[f(x, y)] for (x, y) = m + L z, z standard normal (midpoint rule in z).
double integrate_2d(double mx, double my, double pxx, double pxy, double pyy,
                    const std::function<double(double, double)>& f) {
  const double l11 = std::sqrt(pxx), l21 = pxy / l11, l22 = std::sqrt(pyy - l21 * l21);
  const int n = 1200;
  const double h = 20.0 / n;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double z1 = -10.0 + (i + 0.5) * h, w1 = std::exp(-0.5 * z1 * z1);
    for (int j = 0; j < n; ++j) {
      const double z2 = -10.0 + (j + 0.5) * h;
      sum += w1 * std::exp(-0.5 * z2 * z2) * f(mx + l11 * z1, my + l21 * z1 + l22 * z2);
    }
  }
  return sum * h * h / (2.0 * M_PI);
}

}  // namespace

TEST_CASE("Gaussian moments E[x^a y^b] of a correlated bivariate Gaussian", "[likelihood][gaussian]") {
  const double mx = 0.7, my = -0.4, pxx = 0.3, pxy = -0.12, pyy = 0.2;
  GaussianMoments<double> m;
  m.compute(mx, my, pxx, pxy, pyy, 9, 3);
  for (int a : {0, 1, 2, 3, 5, 9})
    for (int b : {0, 1, 2, 3}) {
      const double q = integrate_2d(mx, my, pxx, pxy, pyy,
                                    [&](double x, double y) { return std::pow(x, a) * std::pow(y, b); });
      INFO("a = " << a << ", b = " << b);
      CHECK(m(a, b) == Approx(q).epsilon(1e-7).margin(1e-9));
    }
}

TEST_CASE("closed-form expectations of sign(y), y|y|, |y| and hinges", "[likelihood][gaussian]") {
  for (double m : {-1.3, -0.05, 0.0, 0.4, 2.5})
    for (double s : {0.05, 0.3, 1.7}) {
      INFO("m = " << m << ", s = " << s);
      auto sign = [](double y) { return double((y > 0) - (y < 0)); };
      CHECK(expect_sign(m, s) == Approx(integrate_1d(m, s, sign, 0.0)).margin(1e-7));
      CHECK(expect_y_abs_y(m, s) ==
            Approx(integrate_1d(m, s, [](double y) { return y * std::abs(y); }, 0.0)).margin(1e-7));
      CHECK(expect_abs(m, s) == Approx(integrate_1d(m, s, [](double y) { return std::abs(y); }, 0.0)).margin(1e-7));
      for (double g : {-0.5, 0.3, 1.0}) {
        CHECK(expect_hinge(m, s, g) ==
              Approx(integrate_1d(m, s, [&](double x) { return std::max(x - g, 0.0); }, g)).margin(1e-7));
        CHECK(expect_step(m, s, g) ==
              Approx(integrate_1d(m, s, [&](double x) { return x > g ? 1.0 : 0.0; }, g)).margin(1e-6));
      }
      // Stein: E[sign'(y)] is the derivative of E[sign(y)] with respect to the mean
      const double e = 1e-6;
      CHECK(expect_dsign(m, s) ==
            Approx((expect_sign(m + e, s) - expect_sign(m - e, s)) / (2 * e)).epsilon(1e-5).margin(1e-8));
    }
}

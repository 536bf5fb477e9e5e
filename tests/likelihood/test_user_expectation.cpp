// The filter's expectations of users' expression terms (user_expectation.hpp) against closed
// forms (a step, a hinge, |y|, a polynomial of both variables) and direct numerical
// integration, and their Jet derivatives against central differences of the values.
#include <catch2/catch.hpp>

#include <cmath>

#include <ceres/jet.h>

#include "vehs/likelihood/detail/user_expectation.hpp"

using namespace vehs::likelihood::detail;
using vehs::Term;

namespace {
double Phi(double d) { return 0.5 * std::erfc(-d / std::sqrt(2.0)); }
double phi(double d) { return std::exp(-0.5 * d * d) / std::sqrt(2.0 * M_PI); }

/// E[f(y)] for y ~ N(m, s²) by a fine midpoint rule over ±12 s.
template <class F>
double integrate(double m, double s, F f) {
  const int n = 400000;
  const double h = 24.0 * s / n;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double y = m - 12.0 * s + (i + 0.5) * h;
    sum += f(y) * phi((y - m) / s) * h / s;
  }
  return sum;
}
}  // namespace

TEST_CASE("user term expectations of one variable are exact for steps and hinges", "[likelihood][user]") {
  const Term step = Term::parse("(y>0)"), hinge = Term::parse("y*(y>0)"), absy = Term::parse("abs(y)");
  for (double m : {-0.31, -0.02, 0.0, 0.013, 0.2, 1.7})
    for (double s : {0.01, 0.1, 0.5}) {
      CAPTURE(m, s);
      const double d = m / s, pyy = s * s;
      auto e = expect_user(step, 0.3, m, 0.04, 0.001, pyy, 0.0);
      CHECK(e.value == Approx(Phi(d)).margin(1e-10));
      CHECK(e.dy == Approx(phi(d) / s).margin(1e-8 / s));
      CHECK(e.dx == 0.0);
      e = expect_user(hinge, 0.3, m, 0.04, 0.001, pyy, 0.0);
      CHECK(e.value == Approx(m * Phi(d) + s * phi(d)).margin(1e-10 * (1 + std::abs(m))));
      CHECK(e.dy == Approx(Phi(d)).margin(1e-9));
      e = expect_user(absy, 0.3, m, 0.04, 0.001, pyy, 0.0);
      CHECK(e.value == Approx(m * std::erf(d / std::sqrt(2.0)) + 2 * s * phi(d)).margin(1e-10 * (1 + std::abs(m))));
    }
}

TEST_CASE("user term expectations of smooth functions match integration", "[likelihood][user]") {
  const Term t = Term::parse("tanh(y/0.05)+0.3*y^3");
  for (double m : {-0.2, 0.01, 0.08})
    for (double s : {0.02, 0.1}) {
      CAPTURE(m, s);
      const auto e = expect_user(t, 0.0, m, 1.0, 0.0, s * s, 0.0);
      const double ref = integrate(m, s, [](double y) { return std::tanh(y / 0.05) + 0.3 * y * y * y; });
      const double dref = integrate(m, s, [](double y) {
        const double th = std::tanh(y / 0.05);
        return (1 - th * th) / 0.05 + 0.9 * y * y;
      });
      // the interpolant's bound h²/8·max|g″| with h = s/8, max|g″| = 0.77/0.05² + 1.8·|y|max
      const double bound = (s / 8) * (s / 8) / 8 * (0.77 / 0.0025 + 1.8 * (std::abs(m) + 8 * s));
      CHECK(std::abs(e.value - ref) < bound);
      CHECK(e.dy == Approx(dref).epsilon(0.02));
    }
}

TEST_CASE("user term expectations of two variables are exact for polynomials", "[likelihood][user]") {
  const Term t = Term::parse("x*y^2+0.5*x^3");
  const double mx = 0.4, my = -0.7, pxx = 0.09, pxy = -0.02, pyy = 0.05;
  const auto e = expect_user(t, mx, my, pxx, pxy, pyy, 0.0);
  const double exy2 = mx * (my * my + pyy) + 2.0 * my * pxy, ex3 = mx * mx * mx + 3.0 * mx * pxx;
  CHECK(e.value == Approx(exy2 + 0.5 * ex3).epsilon(1e-12));
  CHECK(e.dx == Approx(my * my + pyy + 1.5 * (mx * mx + pxx)).epsilon(1e-10));
  CHECK(e.dy == Approx(2.0 * (mx * my + pxy)).epsilon(1e-10));
}

TEST_CASE("user term expectation derivatives are those of the values", "[likelihood][user]") {
  using J = ceres::Jet<double, 3>;
  for (const char* text : {"(y>0)", "y*(y<0)", "x*tanh(y/0.1)", "(x>0.2)*(x-0.2)"}) {
    CAPTURE(text);
    const Term t = Term::parse(text);
    const double mx = 0.25, my = 0.03, pxx = 0.01, pxy = 0.002, pyy = 0.004;
    // slots: my, pyy, mx
    const auto e = expect_user(t, J(mx, 2), J(my, 0), J(pxx), J(pxy), J(pyy, 1), 0.0);
    const double h = 1e-6;
    auto val = [&](double dmx, double dmy, double dpyy) {
      return expect_user(t, mx + dmx, my + dmy, pxx, pxy, pyy + dpyy, 0.0).value;
    };
    CHECK(e.value.a == Approx(val(0, 0, 0)).epsilon(1e-13));
    const double dmy = (val(0, h, 0) - val(0, -h, 0)) / (2 * h), dpyy = (val(0, 0, h) - val(0, 0, -h)) / (2 * h),
                 dmx = (val(h, 0, 0) - val(-h, 0, 0)) / (2 * h);
    // one variable: the closed form's own derivatives (to the differences' rounding); two: the
    // importance weights give the exact integral's derivative, the differences the 12-point
    // rule's, which agree to the rule's accuracy
    const double tol = t.fn->uses_x() && t.fn->uses_y() ? 1e-3 : 1e-5;
    CHECK(e.value.v[0] == Approx(dmy).margin(tol * (1 + std::abs(dmy))));
    CHECK(e.value.v[1] == Approx(dpyy).margin(tol * (1 + std::abs(dpyy))));
    CHECK(e.value.v[2] == Approx(dmx).margin(tol * (1 + std::abs(dmx))));
    // Stein: E[∂y g] = ∂E[g]/∂my
    CHECK(e.dy.a == Approx(dmy).margin(tol * (1 + std::abs(dmy))));
  }
}

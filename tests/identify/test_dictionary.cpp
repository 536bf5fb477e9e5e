// Block evaluation of dictionaries against the reference term definitions of vehs::Term.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

#include "vehs/identify/dictionary.hpp"
#include "vehs/identify/smoothed_sign.hpp"
#include "vehs/sim/random.hpp"
#include "stat_bounds.hpp"

using namespace vehs;
using namespace vehs::identify;

TEST_CASE("dictionary blocks match Term values and derivatives", "[identify][dictionary]") {
  std::vector<Term> lib = paper_drift_library(11, 3);
  for (const char* n : {"sign(y)", "y*|y|", "x^3*y^2", "y^3", "u", "x^12"}) lib.push_back(Term::parse(n));
  std::mt19937_64 gen(5);
  std::normal_distribution<double> N01;
  for (const std::vector<int>& subset : {std::vector<int>{}, std::vector<int>{3, 5, 11, 13}, std::vector<int>{12, 16}}) {
    Dictionary full(lib);
    const Dictionary d = subset.empty() ? full : full.subset(subset);
    RowBlock b;
    b.m = 173;
    for (int i = 0; i < b.m; ++i) b.x[i] = 1.3 * N01(gen), b.v[i] = N01(gen), b.u[i] = N01(gen);
    std::vector<double> out(static_cast<std::size_t>(d.size()) * kBlockRows), dv(out.size()), d2(out.size()),
        dx(out.size()), scratch(d.scratch_size());
    d.values(b, out.data(), kBlockRows, scratch.data());
    d.d_dv(b, dv.data(), kBlockRows, scratch.data());
    d.d2_dv2(b, d2.data(), kBlockRows, scratch.data());
    d.d_dx(b, dx.data(), kBlockRows, scratch.data());
    for (int k = 0; k < d.size(); ++k) {
      const Term& t = d.term(k);
      CAPTURE(t.name());
      for (int i = 0; i < b.m; ++i) {
        const double ref = t.value(b.x[i], b.v[i], b.u[i]);
        REQUIRE(out[static_cast<std::size_t>(k * kBlockRows + i)] == Approx(ref).epsilon(1e-14).margin(1e-300));
        REQUIRE(dx[static_cast<std::size_t>(k * kBlockRows + i)] == Approx(t.d_dx(b.x[i], b.v[i])).epsilon(1e-14));
      }
    }
    const auto& vt = d.velocity_terms();
    for (std::size_t j = 0; j < vt.size(); ++j) {
      const Term& t = d.term(vt[j]);
      CAPTURE(t.name());
      CHECK(t.depends_on_y());
      for (int i = 0; i < b.m; ++i) {
        if (t.kind == TermKind::SignY) continue;  // box kernel, checked below
        REQUIRE(dv[j * kBlockRows + static_cast<std::size_t>(i)] == Approx(t.d_dy(b.x[i], b.v[i])).epsilon(1e-14));
        REQUIRE(d2[j * kBlockRows + static_cast<std::size_t>(i)] == Approx(t.d2_dy2(b.x[i], b.v[i])).epsilon(1e-14));
      }
    }
  }
}

TEST_CASE("the sign(y) derivative kernel integrates to 2 (∂ sign(v)/∂v = 2δ(v))", "[identify][dictionary]") {
  Dictionary d({Term::sign_y()});
  d.set_sign_kernel_halfwidth(0.1);
  RowBlock b;
  b.m = kBlockRows;
  const double step = 1.0 / kBlockRows;  // v over [-0.5, 0.5)
  for (int i = 0; i < b.m; ++i) b.x[i] = 0.0, b.v[i] = -0.5 + (i + 0.5) * step, b.u[i] = 0.0;
  std::vector<double> dv(kBlockRows), scratch(d.scratch_size());
  d.d_dv(b, dv.data(), kBlockRows, scratch.data());
  double integral = 0.0;
  for (double v : dv) integral += v * step;
  CHECK(integral == Approx(2.0).epsilon(0.02));
}

// Deterministic: the closed forms of smoothed_sign.hpp (limits, oddness, derivatives by finite
// differences, ∫S' = 2) and the dictionary's use of them.
TEST_CASE("the smoothed sign: limits, derivatives and the dictionary's sign(y) column", "[identify][dictionary]") {
  const double c = 0.3, d = 0.05;  // w(s)² = c(s² + 1/3) + d
  CHECK(smoothed_sign(0.0, c, d).value == 0.0);
  CHECK(smoothed_sign(10.0, c, d).value == 1.0);
  CHECK(smoothed_sign(-10.0, c, d).value == -1.0);
  double integral = 0.0;
  for (double v = -4.0; v < 4.0; v += 1e-3) {
    const auto s = smoothed_sign(v + 5e-4, c, d);
    integral += s.d1 * 1e-3;
    CHECK(smoothed_sign(-(v + 5e-4), c, d).value == Approx(-s.value).margin(1e-15));
  }
  CHECK(integral == Approx(2.0).epsilon(1e-9));
  for (double v : {-0.9, -0.2, 0.05, 0.3, 0.7}) {
    const double e = 1e-5;
    const auto s = smoothed_sign(v, c, d);
    CHECK(s.d1 == Approx((smoothed_sign(v + e, c, d).value - smoothed_sign(v - e, c, d).value) / (2 * e)).epsilon(1e-7));
    CHECK(s.d2 == Approx((smoothed_sign(v + e, c, d).d1 - smoothed_sign(v - e, c, d).d1) / (2 * e)).epsilon(1e-6));
  }
  // the dictionary: S with a22 from the given terms (here 0.2 + 0.1 x², h = 0.5, no sensor noise)
  Dictionary dict({Term::sign_y()});
  dict.set_sign_smoothing(0.5, {{Term::parse("1"), 0.2}, {Term::parse("x^2"), 0.1}}, 1e-6, 0.0);
  RowBlock b;
  b.m = 3;
  b.x[0] = 0.0, b.v[0] = 0.1, b.x[1] = 2.0, b.v[1] = -0.3, b.x[2] = 1.0, b.v[2] = 5.0;
  std::vector<double> out(kBlockRows), dv(kBlockRows), scratch(dict.scratch_size());
  dict.values(b, out.data(), kBlockRows, scratch.data());
  dict.d_dv(b, dv.data(), kBlockRows, scratch.data());
  for (int i = 0; i < 3; ++i) {
    const auto s = smoothed_sign(b.v[i], (0.2 + 0.1 * b.x[i] * b.x[i]) * 0.5, 0.0);
    CHECK(out[static_cast<std::size_t>(i)] == s.value);
    CHECK(dv[static_cast<std::size_t>(i)] == s.d1);
  }
}

// Monte Carlo of the two identities smoothed_sign.hpp rests on, in its local model: over a
// window [−h, h] (h = 1, a22 = 1) the velocity is y(u) = Y − μ∫sign(y) + W(u), Y uniform on
// [−L, L] (flat on the scale √(a22 h)), Euler on 2·100 steps; v̂ = the window average of y,
// tent = the tent average of sign(y), ξ = the tent-weighted noise of the second difference.
//  (1) without friction, E[(tent − S(v̂))·sign(v̂)] = 0, while sign(v̂) in place of S leaves
//      E[(tent − sign(v̂))·sign(v̂)] = −0.785·p(0) (p(0) = 1/(2L): the bias the smoothing removes);
//  (2) with friction μ = 0.15 (μ·q₀ = 0.10), E[ξ S(v̂)] = E[½ S'(v̂)(1 − μ q₀)] — the Itô term
//      with the friction's response — and not E[½ S'(v̂)] (7.8 of its standard errors away).
// Each comparison allows z_bound(3) standard errors (the three checks: 1e-4 in all) plus 2 % of
// the reference for the O(1/steps) discretisation and the neglected O((μq₀)²) = 1 % term; the
// teeth checks below fail with probability Φ(−4.8) = 8e-7 or less.
TEST_CASE("the smoothed sign and the friction's response term on simulated windows (Monte Carlo)",
          "[identify][dictionary]") {
  const int N = 200000, M = 100;
  const double L = 3.5, du = 1.0 / M, mu = 0.15, p0 = 1.0 / (2.0 * L);
  const vehs::sim::CounterRng rng(vehs_test::seed(41));
  double m1 = 0, s1 = 0, m0 = 0, s0 = 0, mxi = 0, sxi = 0, mito = 0, mito0 = 0;
  std::vector<double> z(2 * M);
  for (int n = 0; n < N; ++n) {
    for (int j = 0; j < M; ++j) {
      const auto p = rng.normal_pair(static_cast<std::uint64_t>(n), vehs::sim::Purpose::User, static_cast<std::uint64_t>(j));
      z[static_cast<std::size_t>(2 * j)] = p[0], z[static_cast<std::size_t>(2 * j + 1)] = p[1];
    }
    const double Y = -L + 2.0 * L * rng.uniform(static_cast<std::uint64_t>(n), vehs::sim::Purpose::Initial, 0);
    auto window = [&](double friction, double& vhat, double& tent, double& xi) {
      double y = Y, area = 0.5 * y, t = 0.0;
      xi = 0.0;
      for (int j = 0; j < 2 * M; ++j) {
        const double u_mid = -1.0 + (j + 0.5) * du, u_next = -1.0 + (j + 1) * du;
        const double dw = std::sqrt(du) * z[static_cast<std::size_t>(j)];
        xi += (1.0 - std::abs(u_mid)) * dw;
        y += -friction * static_cast<double>((y > 0) - (y < 0)) * du + dw;
        area += j + 1 < 2 * M ? y : 0.5 * y;
        t += (1.0 - std::abs(u_next)) * static_cast<double>((y > 0) - (y < 0)) * du;
      }
      vhat = 0.5 * area * du;
      tent = t;
    };
    double v, tent, xi;
    window(0.0, v, tent, xi);  // (1)
    const auto S = smoothed_sign(v, 1.0, 0.0);
    const double sg = static_cast<double>((v > 0) - (v < 0));
    const double a = (tent - S.value) * sg;
    m1 += a, s1 += a * a, m0 += (tent - sg) * sg, s0 += (tent - sg) * sg * (tent - sg) * sg;
    window(mu, v, tent, xi);  // (2)
    const auto Sf = smoothed_sign(v, 1.0, 0.0);
    mxi += xi * Sf.value, sxi += xi * Sf.value * xi * Sf.value;
    mito += 0.5 * Sf.d1 * (1.0 - mu * kSignResponse), mito0 += 0.5 * Sf.d1;
  }
  m1 /= N, m0 /= N, mxi /= N, mito /= N, mito0 /= N;
  const double se1 = std::sqrt((s1 / N - m1 * m1) / N), se0 = std::sqrt((s0 / N - m0 * m0) / N), sexi = std::sqrt((sxi / N - mxi * mxi) / N);
  const double zb = vehs_test::z_bound(3);
  INFO("(1) E[(tent - S) sign] = " << m1 << " +- " << se1 << ", E[(tent - sign) sign] = " << m0
                                   << " (theory " << -0.785 * p0 << ")");
  INFO("(2) E[xi S] = " << mxi << " +- " << sexi << ", Ito with response " << mito << ", without " << mito0);
  CHECK(std::abs(m1) <= zb * se1 + 0.02 * 0.785 * p0);
  CHECK(std::abs(m0 + 0.785 * p0) <= zb * se0 + 0.02 * 0.785 * p0);
  CHECK(std::abs(mxi - mito) <= zb * sexi + 0.02 * mito);
  CHECK(std::abs(mxi - mito0) > 3.0 * sexi);  // teeth: the plain Itô term is measurably wrong
}

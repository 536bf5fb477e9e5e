// Block evaluation of dictionaries against the reference term definitions of vehs::Term.
#include <catch2/catch.hpp>

#include <random>

#include "vehs/identify/dictionary.hpp"

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

#include <catch2/catch.hpp>

#include <cmath>

#include "vehs/core/error.hpp"
#include "vehs/core/terms.hpp"

using vehs::Term;

TEST_CASE("term names round-trip through parse and name", "[terms]") {
  for (const char* name : {"1", "x", "x^3", "x^10", "y", "x*y", "x^2*y", "y^3", "x^4*y^2",
                           "sign(y)", "y*|y|", "u"}) {
    CAPTURE(name);
    CHECK(Term::parse(name).name() == name);
  }
}

TEST_CASE("non-canonical or unknown term names are rejected", "[terms]") {
  for (const char* bad : {"", "x^1", "x^0", "y*x", "x^02", "z", "x^", "x**2", "x^2*", "2", "x+",
                          "tanh(z)", "y*(y>0"}) {
    CAPTURE(bad);
    CHECK_THROWS_AS(Term::parse(bad), vehs::Error);
  }
}

TEST_CASE("term values and derivatives match finite differences", "[terms]") {
  const double x = 0.7, y = -1.3, h = 1e-5;
  for (const char* name : {"1", "x", "x^5", "y", "x^2*y", "y^3", "x^3*y^2", "y*|y|"}) {
    CAPTURE(name);
    const Term t = Term::parse(name);
    CHECK(t.d_dx(x, y) == Approx((t.value(x + h, y) - t.value(x - h, y)) / (2 * h)).epsilon(1e-8).margin(1e-9));
    CHECK(t.d_dy(x, y) == Approx((t.value(x, y + h) - t.value(x, y - h)) / (2 * h)).epsilon(1e-8).margin(1e-9));
    CHECK(t.d2_dy2(x, y) ==
          Approx((t.value(x, y + h) - 2 * t.value(x, y) + t.value(x, y - h)) / (h * h)).epsilon(1e-4).margin(1e-5));
  }
  CHECK(Term::sign_y().value(0, 0) == 0.0);
  CHECK(Term::sign_y().value(0, -2) == -1.0);
  CHECK(Term::drive().value(1, 1, 3.5) == 3.5);
}

TEST_CASE("canonical order and duplicate detection", "[terms]") {
  vehs::TermList l{{Term::parse("y"), 1}, {Term::parse("x^3"), 2}, {Term::parse("1"), 3},
                   {Term::parse("sign(y)"), 4}, {Term::parse("x"), 5}};
  vehs::canonicalize(l, "test");
  std::vector<std::string> names;
  for (auto& tc : l) names.push_back(tc.term.name());
  CHECK(names == std::vector<std::string>{"1", "x", "x^3", "y", "sign(y)"});
  l.push_back({Term::parse("x"), 1});
  CHECK_THROWS_AS(vehs::canonicalize(l, "test"), vehs::Error);
}

TEST_CASE("the paper's dictionaries have the sizes of Eq. 11 and 17", "[terms]") {
  auto d = vehs::paper_drift_library(11, 3);
  REQUIRE(d.size() == 14);
  CHECK(d.front().name() == "1");
  CHECK(d[10].name() == "x^10");
  CHECK(d[13].name() == "x^2*y");
  CHECK(vehs::paper_diffusion_library(4).size() == 5);
}

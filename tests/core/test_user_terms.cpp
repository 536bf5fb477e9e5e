// Users' expression terms (vehs/core/user_function.hpp): parsed once, evaluated like the
// catalogue's terms, carried through the change of units, refused with the parser's reason.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include "vehs/core/error.hpp"
#include "vehs/core/model.hpp"
#include "vehs/core/scaling.hpp"
#include "vehs/core/terms.hpp"

using vehs::Term;
using vehs::TermKind;

TEST_CASE("an expression in x y u is a user term named by its text", "[terms][user]") {
  const Term t = Term::parse("-(y > 0) * 0.5 + tanh(y/0.01)");
  CHECK(t.kind == TermKind::User);
  CHECK(t.name() == "-(y>0)*0.5+tanh(y/0.01)");
  CHECK(Term::parse(t.name()) == t);
  CHECK(t.value(0.3, 0.02) == Approx(-0.5 + std::tanh(2.0)).epsilon(1e-15));
  CHECK(t.value(0.3, -0.02) == Approx(std::tanh(-2.0)).epsilon(1e-15));
  CHECK(t.depends_on_y());
  CHECK_FALSE(t.depends_on_u());
  const Term drive = Term::parse("u*x");
  CHECK(drive.depends_on_u());
  CHECK(drive.value(2.0, 0.0, 3.0) == 6.0);
  // white space and a canonical text give the catalogue's term
  CHECK(Term::parse("x^2 * y") == Term::monomial(2, 1));
  CHECK(Term::parse("sign(x)").kind == TermKind::User);
}

TEST_CASE("a user term's derivatives match its closed form", "[terms][user]") {
  const Term t = Term::parse("x^2*tanh(y)+u*sin(x)");
  const double x = 0.7, y = -0.4, u = 1.5, th = std::tanh(y), sech2 = 1.0 - th * th;
  CHECK(t.d_dx(x, y, u) == Approx(2 * x * th + u * std::cos(x)).epsilon(1e-8));
  CHECK(t.d_dy(x, y, u) == Approx(x * x * sech2).epsilon(1e-8));
  CHECK(t.d2_dy2(x, y, u) == Approx(x * x * (-2.0 * th * sech2)).epsilon(1e-5));
  CHECK(t.d2_dx2(x, y, u) == Approx(2 * th - u * std::sin(x)).epsilon(1e-5));
  CHECK(t.d2_dxdy(x, y, u) == Approx(2 * x * sech2).epsilon(1e-5));
}

TEST_CASE("a user term's derivatives leave its jumps out as sign(y)'s do", "[terms][user]") {
  // a step in the stencil: the derivative of its sides (0, 0.5), not a spike of height J/(2h);
  // before, (y>0) at y = 1e-7 gave ∂y 5e5 and ∂yy 5e7, which kicked the Taylor 1.5 scheme
  const Term step = Term::parse("(y>0)+0.5*y*(y>0)"), pure = Term::parse("(y>0)"), smooth = Term::parse("tanh(y/0.01)");
  for (double y : {-3e-7, 0.0, 1e-7, 2e-6, 3e-5}) {
    CAPTURE(y);
    CHECK(std::abs(step.d_dy(0.2, y)) <= 0.5 + 1e-6);
    CHECK(pure.d2_dy2(0.2, y) == 0.0);
  }
  CHECK(step.d_dy(0.2, 0.3) == Approx(0.5).epsilon(1e-8));
  CHECK(step.d_dy(0.2, -0.3) == Approx(0.0).margin(1e-8));
  // a steep but smooth rise keeps its derivative (100 at the origin)
  CHECK(smooth.d_dy(0.0, 0.0) == Approx(100.0).epsilon(1e-6));
  CHECK(smooth.d2_dy2(0.0, 0.005) == Approx(-2e4 * std::tanh(0.5) * (1 - std::tanh(0.5) * std::tanh(0.5))).epsilon(1e-3));
  // a jump in x, the same rule
  const Term stop = Term::parse("(x>0.8)");
  CHECK(std::abs(stop.d_dx(0.8, 0.0)) < 1e-3);
}

TEST_CASE("a bad expression is refused with the parser's reason", "[terms][user]") {
  auto message = [](const char* text) {
    try {
      (void)Term::parse(text);
    } catch (const vehs::Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK(message("tanh(z)").find("Unexpected token \"z\"") != std::string::npos);
  CHECK(message("tanh(z)").find("unknown term 'tanh(z)'") != std::string::npos);
  CHECK(message("3+2").find("uses none of x, y, u") != std::string::npos);
  CHECK(message("y*x").find("expected \"1\"") != std::string::npos);
}

TEST_CASE("a user term follows the change of units", "[terms][user][scaling]") {
  // b2 = -0.8·(y>0.05) − 3·y·|x| in metres and seconds; internal units L = 1e-3, T = 1e-2
  vehs::Model m;
  m.drift = {{Term::parse("(y>0.05)"), -0.8}, {Term::parse("y*abs(x)"), -3.0}, {Term::monomial(1), -4.0}};
  const vehs::Scales s{1e-3, 1e-2, 1.0};
  const vehs::Model internal = vehs::to_internal(m, s);
  const double acceleration = s.length / (s.time * s.time);
  for (double x : {-2e-3, 5e-4, 3e-3})
    for (double y : {-0.2, 0.03, 0.07, 0.4}) {
      CAPTURE(x, y);
      const double xi = x / s.length, yi = y / (s.length / s.time);
      CHECK(internal.b2(xi, yi) * acceleration == Approx(m.b2(x, y)).epsilon(1e-12));
    }
  const vehs::Model back = vehs::to_physical(internal, s);
  CHECK(back.b2(1e-3, 0.1) == Approx(m.b2(1e-3, 0.1)).epsilon(1e-12));
  CHECK(back.drift[0].term == m.drift[0].term);
  // a library in internal units evaluates the physical function
  const auto lib = vehs::to_internal(std::vector<Term>{Term::parse("(y>0.05)")}, s);
  CHECK(lib[0].value(0.0, 0.06 / (s.length / s.time)) == 1.0);
  CHECK(lib[0].value(0.0, 0.04 / (s.length / s.time)) == 0.0);
}

TEST_CASE("user terms evaluate from several threads at once", "[terms][user]") {
  const Term t = Term::parse("x*y+sin(x)");
  std::vector<double> error(4, 0.0);
  std::vector<std::thread> threads;
  for (int k = 0; k < 4; ++k)
    threads.emplace_back([&, k] {
      for (int i = 0; i < 20000; ++i) {
        const double x = 1e-4 * i + k, y = 0.5 - k;
        error[std::size_t(k)] += std::abs(t.value(x, y) - (x * y + std::sin(x)));
      }
    });
  for (auto& th : threads) th.join();
  for (double e : error) CHECK(e == 0.0);
}

TEST_CASE("a user term returns from internal units exactly at every power of ten", "[core][user]") {
  // the factors compound to 1 + 2.2e-16 at 1e-9 · 1e9 in floating point: the round trip must give
  // the parsed function back, equal to it (a requested term is found again by equality)
  const vehs::Term t = vehs::Term::parse("-x^3");
  for (int e = -12; e <= 12; ++e) {
    const double s = std::pow(10.0, e);
    const vehs::Term back = vehs::rescaled(vehs::rescaled(t, s, s, s, 1.0 / s), 1.0 / s, 1.0 / s, 1.0 / s, s);
    CAPTURE(e);
    CHECK(back == t);
  }
}

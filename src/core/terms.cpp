#include "vehs/core/terms.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <tuple>

#include "vehs/core/error.hpp"

namespace vehs {

Term Term::monomial(int px, int py) {
  require(px >= 0 && py >= 0, "monomial powers must be non-negative");
  return Term{TermKind::Monomial, px, py, nullptr};
}

namespace {

const char* const kGrammar =
    "expected \"1\", a monomial like \"x\", \"x^3\", \"y\", \"x^2*y\", \"y^3\", or one of "
    "\"sign(y)\", \"y*|y|\", \"u\"";

// Parses "x", "x^N", "y", "y^N" into (variable, power); returns false on anything else.
bool parse_factor(std::string_view f, char& var, int& power) {
  if (f.empty() || (f[0] != 'x' && f[0] != 'y')) return false;
  var = f[0];
  if (f.size() == 1) {
    power = 1;
    return true;
  }
  if (f[1] != '^' || f.size() < 3) return false;
  const char* b = f.data() + 2;
  const char* e = f.data() + f.size();
  auto [p, ec] = std::from_chars(b, e, power);
  // '^' only for powers >= 2, no leading zeros or signs
  return ec == std::errc() && p == e && power >= 2 && power <= 64 && *b != '0';
}

/// The canonical grammar into `out`; false on anything else.
bool parse_canonical(std::string_view name, Term& out);

}  // namespace

Term Term::parse(std::string_view name) {
  Term t;
  if (parse_canonical(name, t)) return t;
  std::string compact;
  for (char c : name)
    if (c != ' ' && c != '\t') compact += c;
  if (compact != name && parse_canonical(compact, t)) return t;
  // a product of powers of x and y must be written canonically ("x^2*y", not "y*x^2" or "x^02"):
  // an expression for it would be a second name of the same term
  if (compact.find_first_not_of("xy0123456789^*") == std::string::npos)
    throw Error("unknown term '" + std::string(name) + "': " + kGrammar);
  try {
    return user(UserFunction::parse(name));
  } catch (const Error& e) {
    throw Error("unknown term '" + std::string(name) + "': " + kGrammar +
                ", or an expression in x, y, u (" + e.what() + ")");
  }
}

namespace {

bool parse_canonical(std::string_view name, Term& out) {
  auto fail = [] { return false; };
  auto done = [&](Term t) {
    out = std::move(t);
    return true;
  };
  if (name == "1") return done(Term::monomial(0, 0));
  if (name == "sign(y)") return done(Term::sign_y());
  if (name == "y*|y|") return done(Term::y_abs_y());
  if (name == "u") return done(Term::drive());
  int px = 0, py = 0;
  const auto star = name.find('*');
  std::string_view first = name.substr(0, star);
  char v1 = 0;
  int p1 = 0;
  if (!parse_factor(first, v1, p1)) return fail();
  if (star == std::string_view::npos) {
    (v1 == 'x' ? px : py) = p1;
    return done(Term::monomial(px, py));
  }
  std::string_view second = name.substr(star + 1);
  char v2 = 0;
  int p2 = 0;
  if (v1 != 'x' || !parse_factor(second, v2, p2) || v2 != 'y') return fail();
  return done(Term::monomial(p1, p2));
}

}  // namespace

std::string Term::name() const {
  switch (kind) {
    case TermKind::SignY: return "sign(y)";
    case TermKind::YAbsY: return "y*|y|";
    case TermKind::Drive: return "u";
    case TermKind::User: return fn->text();
    case TermKind::Monomial: break;
  }
  if (px == 0 && py == 0) return "1";
  auto factor = [](char v, int p) {
    std::string s(1, v);
    if (p >= 2) s += "^" + std::to_string(p);
    return s;
  };
  std::string s;
  if (px > 0) s = factor('x', px);
  if (py > 0) s += (s.empty() ? "" : "*") + factor('y', py);
  return s;
}

bool Term::depends_on_y() const {
  switch (kind) {
    case TermKind::Monomial: return py > 0;
    case TermKind::Drive: return false;
    case TermKind::User: return fn->uses_y();
    default: return true;
  }
}

namespace {
inline double sgn(double y) { return (y > 0) - (y < 0); }

// Central differences of a user's function: steps relative to the point (internal units are
// O(1)). A jump inside the stencil is left out, as sign(y)'s derivative is 0 almost everywhere
// (a spike of height J/h would kick a Taylor step, or the filter's step rule, wherever the state
// crosses it): a rise over [z − h, z + h] more than 4× the rises beside it, at the same spacing,
// is a jump, and the sides' slopes stand in for it.
constexpr double kStep1 = 1e-6, kStep2 = 1e-4;
inline double step(double z, double h) { return h * (1.0 + std::abs(z)); }
inline bool is_jump(double rise, double left, double right, double scale) {
  return std::abs(rise) > 4.0 * std::max(std::abs(left), std::abs(right)) && std::abs(rise) > 1e-12 * scale;
}
/// g′(z) for g(z) = `at(z)`.
template <class G>
double slope_without_jumps(const G& at, double z, double h) {
  const double gm = at(z - h), gp = at(z + h), rise = gp - gm;
  const double left = gm - at(z - 3.0 * h), right = at(z + 3.0 * h) - gp;
  if (is_jump(rise, left, right, std::abs(gm) + std::abs(gp))) return (left + right) / (4.0 * h);
  return rise / (2.0 * h);
}
/// g″(z) for g(z) = `at(z)`.
template <class G>
double curvature_without_jumps(const G& at, double z, double h) {
  const double g0 = at(z), gm = at(z - h), gp = at(z + h);
  const double dm = g0 - gm, dp = gp - g0;
  const double om = gm - at(z - 2.0 * h), op = at(z + 2.0 * h) - gp;
  const double inner = std::abs(dm) > std::abs(dp) ? dm : dp;
  if (is_jump(inner, om, op, std::abs(gm) + std::abs(gp))) return (op - om) / (3.0 * h * h);
  return (dp - dm) / (h * h);
}
double user_dx(const UserFunction& f, double x, double y, double u) {
  return slope_without_jumps([&](double z) { return f(z, y, u); }, x, step(x, kStep1));
}
double user_dy(const UserFunction& f, double x, double y, double u) {
  return slope_without_jumps([&](double z) { return f(x, z, u); }, y, step(y, kStep1));
}
double user_dxx(const UserFunction& f, double x, double y, double u) {
  return curvature_without_jumps([&](double z) { return f(z, y, u); }, x, step(x, kStep2));
}
double user_dyy(const UserFunction& f, double x, double y, double u) {
  return curvature_without_jumps([&](double z) { return f(x, z, u); }, y, step(y, kStep2));
}
double user_dxy(const UserFunction& f, double x, double y, double u) {
  const double hx = step(x, kStep2), hy = step(y, kStep2);
  return (f(x + hx, y + hy, u) - f(x + hx, y - hy, u) - f(x - hx, y + hy, u) + f(x - hx, y - hy, u)) / (4.0 * hx * hy);
}
// d/dz z^n, d²/dz² z^n
inline double dpow(double z, int n) { return n == 0 ? 0.0 : n * ipow(z, n - 1); }
inline double d2pow(double z, int n) { return n < 2 ? 0.0 : n * (n - 1) * ipow(z, n - 2); }
}  // namespace

double Term::value(double x, double y, double u) const {
  switch (kind) {
    case TermKind::Monomial: return ipow(x, px) * ipow(y, py);
    case TermKind::SignY: return sgn(y);
    case TermKind::YAbsY: return y * std::abs(y);
    case TermKind::Drive: return u;
    case TermKind::User: return (*fn)(x, y, u);
  }
  return 0.0;
}

double Term::d_dx(double x, double y, double u) const {
  if (kind == TermKind::User) return user_dx(*fn, x, y, u);
  return kind == TermKind::Monomial ? dpow(x, px) * ipow(y, py) : 0.0;
}

double Term::slope_dx(double x, double y, double hx, double u) const {
  if (kind != TermKind::User || !(hx > 0.0)) return d_dx(x, y, u);
  return ((*fn)(x + hx, y, u) - (*fn)(x - hx, y, u)) / (2.0 * hx);
}

double Term::slope_dy(double x, double y, double hy, double u) const {
  if (kind != TermKind::User || !(hy > 0.0)) return d_dy(x, y, u);
  return ((*fn)(x, y + hy, u) - (*fn)(x, y - hy, u)) / (2.0 * hy);
}

double Term::d_dy(double x, double y, double u) const {
  switch (kind) {
    case TermKind::Monomial: return ipow(x, px) * dpow(y, py);
    case TermKind::YAbsY: return 2.0 * std::abs(y);
    case TermKind::User: return user_dy(*fn, x, y, u);
    default: return 0.0;
  }
}

double Term::d2_dy2(double x, double y, double u) const {
  switch (kind) {
    case TermKind::Monomial: return ipow(x, px) * d2pow(y, py);
    case TermKind::YAbsY: return 2.0 * sgn(y);
    case TermKind::User: return user_dyy(*fn, x, y, u);
    default: return 0.0;
  }
}

double Term::d2_dx2(double x, double y, double u) const {
  if (kind == TermKind::User) return user_dxx(*fn, x, y, u);
  return kind == TermKind::Monomial ? d2pow(x, px) * ipow(y, py) : 0.0;
}

double Term::d2_dxdy(double x, double y, double u) const {
  if (kind == TermKind::User) return user_dxy(*fn, x, y, u);
  return kind == TermKind::Monomial ? dpow(x, px) * dpow(y, py) : 0.0;
}

Term rescaled(const Term& t, double kx, double ky, double ku, double kvalue) {
  if (t.kind != TermKind::User) return t;
  return Term::user(t.fn->rescaled(kx, ky, ku, kvalue));
}

bool operator<(const Term& a, const Term& b) {
  if (a.kind == TermKind::User && b.kind == TermKind::User)
    return std::make_tuple(a.fn->text(), a.fn->scales(), a.fn->value_factor()) <
           std::make_tuple(b.fn->text(), b.fn->scales(), b.fn->value_factor());
  return std::make_tuple(static_cast<int>(a.kind), a.py, a.px) <
         std::make_tuple(static_cast<int>(b.kind), b.py, b.px);
}

bool operator==(const Term& a, const Term& b) {
  if (a.kind == TermKind::User || b.kind == TermKind::User)
    return a.kind == b.kind && a.fn->text() == b.fn->text() && a.fn->scales() == b.fn->scales() &&
           a.fn->value_factor() == b.fn->value_factor();
  return a.kind == b.kind && a.px == b.px && a.py == b.py;
}

std::vector<Term> terms_of(const TermList& terms) {
  std::vector<Term> t;
  t.reserve(terms.size());
  for (const auto& tc : terms) t.push_back(tc.term);
  return t;
}

double evaluate(const TermList& terms, double x, double y, double u) {
  double s = 0.0;
  for (const auto& tc : terms) s += tc.coef * tc.term.value(x, y, u);
  return s;
}

double coefficient(const TermList& terms, const Term& term) {
  for (const auto& tc : terms)
    if (tc.term == term) return tc.coef;
  return 0.0;
}

void canonicalize(TermList& terms, const std::string& what) {
  std::sort(terms.begin(), terms.end(),
            [](const TermCoef& a, const TermCoef& b) { return a.term < b.term; });
  for (std::size_t i = 1; i < terms.size(); ++i)
    if (terms[i].term == terms[i - 1].term)
      throw Error(what + ": term '" + terms[i].term.name() + "' appears twice");
}

std::vector<Term> paper_drift_library(int K1, int K2) {
  require(K1 >= 0 && K2 >= 0 && K1 + K2 > 0, "drift library sizes K1, K2 must be >= 0");
  std::vector<Term> lib;
  for (int i = 0; i < K1; ++i) lib.push_back(Term::monomial(i, 0));
  for (int i = 0; i < K2; ++i) lib.push_back(Term::monomial(i, 1));
  return lib;
}

std::vector<Term> paper_diffusion_library(int M) {
  require(M >= 0, "diffusion library size M must be >= 0");
  std::vector<Term> lib;
  for (int i = 0; i <= M; ++i) lib.push_back(Term::monomial(i, 0));
  return lib;
}

}  // namespace vehs

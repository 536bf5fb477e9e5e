#include "vehs/core/terms.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <tuple>

#include "vehs/core/error.hpp"

namespace vehs {

Term Term::monomial(int px, int py) {
  require(px >= 0 && py >= 0, "monomial powers must be non-negative");
  return Term{TermKind::Monomial, px, py};
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

}  // namespace

Term Term::parse(std::string_view name) {
  auto fail = [&]() -> Term {
    throw Error("unknown term '" + std::string(name) + "': " + kGrammar);
  };
  if (name == "1") return monomial(0, 0);
  if (name == "sign(y)") return sign_y();
  if (name == "y*|y|") return y_abs_y();
  if (name == "u") return drive();
  int px = 0, py = 0;
  const auto star = name.find('*');
  std::string_view first = name.substr(0, star);
  char v1 = 0;
  int p1 = 0;
  if (!parse_factor(first, v1, p1)) return fail();
  if (star == std::string_view::npos) {
    (v1 == 'x' ? px : py) = p1;
    return monomial(px, py);
  }
  std::string_view second = name.substr(star + 1);
  char v2 = 0;
  int p2 = 0;
  if (v1 != 'x' || !parse_factor(second, v2, p2) || v2 != 'y') return fail();
  return monomial(p1, p2);
}

std::string Term::name() const {
  switch (kind) {
    case TermKind::SignY: return "sign(y)";
    case TermKind::YAbsY: return "y*|y|";
    case TermKind::Drive: return "u";
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

namespace {
inline double sgn(double y) { return (y > 0) - (y < 0); }
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
  }
  return 0.0;
}

double Term::d_dx(double x, double y) const {
  return kind == TermKind::Monomial ? dpow(x, px) * ipow(y, py) : 0.0;
}

double Term::d_dy(double x, double y) const {
  switch (kind) {
    case TermKind::Monomial: return ipow(x, px) * dpow(y, py);
    case TermKind::YAbsY: return 2.0 * std::abs(y);
    default: return 0.0;
  }
}

double Term::d2_dy2(double x, double y) const {
  switch (kind) {
    case TermKind::Monomial: return ipow(x, px) * d2pow(y, py);
    case TermKind::YAbsY: return 2.0 * sgn(y);
    default: return 0.0;
  }
}

double Term::d2_dx2(double x, double y) const {
  return kind == TermKind::Monomial ? d2pow(x, px) * ipow(y, py) : 0.0;
}

double Term::d2_dxdy(double x, double y) const {
  return kind == TermKind::Monomial ? dpow(x, px) * dpow(y, py) : 0.0;
}

bool operator<(const Term& a, const Term& b) {
  return std::make_tuple(static_cast<int>(a.kind), a.py, a.px) <
         std::make_tuple(static_cast<int>(b.kind), b.py, b.px);
}

bool operator==(const Term& a, const Term& b) {
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

#pragma once
// Terms of the drift b2(x, y, u) and diffusion a22(x, y) dictionaries, with the names of
// docs/model-file.md: "1", "x", "x^3", "y", "x^2*y", "y^3", "sign(y)", "y*|y|", "u", and any
// expression in x, y, u a user writes ("tanh(y/0.01)", "y*(y>0)": vehs/core/user_function.hpp).
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "vehs/core/user_function.hpp"

namespace vehs {

enum class TermKind {
  Monomial,  ///< x^px * y^py (px, py >= 0); "1" when both are zero
  SignY,     ///< sign(y), with sign(0) = 0 (Coulomb friction)
  YAbsY,     ///< y*|y| (quadratic / air damping)
  Drive,     ///< u, a recorded drive read from the measurement file
  User,      ///< a user's expression in x, y, u (Term::fn)
};

struct Term {
  TermKind kind = TermKind::Monomial;
  int px = 0;  ///< power of x (Monomial only)
  int py = 0;  ///< power of y (Monomial only)
  std::shared_ptr<const UserFunction> fn;  ///< the expression (User only)

  static Term monomial(int px, int py = 0);
  static Term sign_y() { return Term{TermKind::SignY, 0, 0, nullptr}; }
  static Term y_abs_y() { return Term{TermKind::YAbsY, 0, 0, nullptr}; }
  static Term drive() { return Term{TermKind::Drive, 0, 0, nullptr}; }
  static Term user(std::shared_ptr<const UserFunction> f) { return Term{TermKind::User, 0, 0, std::move(f)}; }

  /// Parses a canonical term name, or else an expression in x, y, u (a User term); throws
  /// vehs::Error naming the text, the grammar and the expression parser's reason.
  static Term parse(std::string_view name);
  /// The canonical name ("x^2*y").
  std::string name() const;

  bool depends_on_y() const;
  bool depends_on_u() const { return kind == TermKind::Drive || (kind == TermKind::User && fn->uses_u()); }
  bool is_user() const { return kind == TermKind::User; }
  bool is_polynomial() const { return kind == TermKind::Monomial; }

  double value(double x, double y, double u = 0.0) const;
  /// Derivatives (central differences for a User term, 0 where it jumps)
  double d_dx(double x, double y, double u = 0.0) const;    ///< ∂/∂x (0 for u)
  double d_dy(double x, double y, double u = 0.0) const;    ///< ∂/∂y (0 almost everywhere for sign(y))
  double d2_dy2(double x, double y, double u = 0.0) const;  ///< ∂²/∂y²
  double d2_dx2(double x, double y, double u = 0.0) const;  ///< ∂²/∂x²
  double d2_dxdy(double x, double y, double u = 0.0) const; ///< ∂²/∂x∂y
  /// ∂/∂x and ∂/∂y as a step-size rule sees them at resolution hx, hy: the exact derivative of
  /// the grammar's terms (0 across sign(y)'s jump), a central difference over ±h of a User term
  /// (a jump J reads J/(2h), not the spike of d_dx's own small stencil).
  double slope_dx(double x, double y, double hx, double u = 0.0) const;
  double slope_dy(double x, double y, double hy, double u = 0.0) const;
};

/// The term of internal units (vehs/core/scaling.hpp) for a User term: its function of
/// (kx·x, ky·y, ku·u) times kvalue; any other term unchanged.
Term rescaled(const Term& t, double kx, double ky, double ku, double kvalue = 1.0);

/// Canonical order: monomials by (py, px), then sign(y), y*|y|, u, user terms by text.
bool operator<(const Term& a, const Term& b);
bool operator==(const Term& a, const Term& b);
inline bool operator!=(const Term& a, const Term& b) { return !(a == b); }

/// x^n for small non-negative n (exact repeated multiplication).
inline double ipow(double x, int n) {
  double r = 1.0;
  for (int i = 0; i < n; ++i) r *= x;
  return r;
}

struct TermCoef {
  Term term;
  double coef = 0.0;
};
using TermList = std::vector<TermCoef>;

/// The terms of a list, in its order.
std::vector<Term> terms_of(const TermList& terms);

/// Σ coef·term(x, y, u).
double evaluate(const TermList& terms, double x, double y, double u = 0.0);
/// Looks up a coefficient; 0 when the term is absent.
double coefficient(const TermList& terms, const Term& term);
/// Sorts into canonical order; throws vehs::Error on a duplicate term (naming `what`).
void canonicalize(TermList& terms, const std::string& what);

/// The paper's dictionaries (Eq. 11 and 17): drift [1, x, …, x^(K1−1), y, x·y, …, x^(K2−1)·y],
/// diffusion [1, x, …, x^M].
std::vector<Term> paper_drift_library(int K1 = 11, int K2 = 3);
std::vector<Term> paper_diffusion_library(int M = 4);

}  // namespace vehs

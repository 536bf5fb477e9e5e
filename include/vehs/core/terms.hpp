#pragma once
// Terms of the drift b2(x, y, u) and diffusion a22(x, y) dictionaries, with the names of
// docs/model-file.md: "1", "x", "x^3", "y", "x^2*y", "y^3", "sign(y)", "y*|y|", "u".
#include <string>
#include <string_view>
#include <vector>

namespace vehs {

enum class TermKind {
  Monomial,  ///< x^px * y^py (px, py >= 0); "1" when both are zero
  SignY,     ///< sign(y), with sign(0) = 0 (Coulomb friction)
  YAbsY,     ///< y*|y| (quadratic / air damping)
  Drive,     ///< u, a recorded drive read from the measurement file
};

struct Term {
  TermKind kind = TermKind::Monomial;
  int px = 0;  ///< power of x (Monomial only)
  int py = 0;  ///< power of y (Monomial only)

  static Term monomial(int px, int py = 0);
  static Term sign_y() { return Term{TermKind::SignY, 0, 0}; }
  static Term y_abs_y() { return Term{TermKind::YAbsY, 0, 0}; }
  static Term drive() { return Term{TermKind::Drive, 0, 0}; }

  /// Parses a canonical term name; throws vehs::Error naming the text and the grammar.
  static Term parse(std::string_view name);
  /// The canonical name ("x^2*y").
  std::string name() const;

  bool depends_on_y() const { return kind != TermKind::Monomial ? kind != TermKind::Drive : py > 0; }
  bool depends_on_u() const { return kind == TermKind::Drive; }
  bool is_polynomial() const { return kind == TermKind::Monomial; }

  double value(double x, double y, double u = 0.0) const;
  double d_dx(double x, double y) const;    ///< ∂/∂x (0 for u)
  double d_dy(double x, double y) const;    ///< ∂/∂y (0 almost everywhere for sign(y))
  double d2_dy2(double x, double y) const;  ///< ∂²/∂y²
  double d2_dx2(double x, double y) const;  ///< ∂²/∂x²
  double d2_dxdy(double x, double y) const; ///< ∂²/∂x∂y
};

/// Canonical order: monomials by (py, px), then sign(y), y*|y|, u.
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

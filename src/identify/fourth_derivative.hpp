#pragma once
// Internal: the O(h²) error of the central second difference, removed from the acceleration
// target of the uli and noisy estimators (Options::discretization_correction).
#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "vehs/core/terms.hpp"

namespace vehs::identify::detail {

/// The leading discretisation error of the central second difference over a smooth path:
/// (x(t+h) − 2x(t) + x(t−h))/h² = ẍ + (h²/12)·x⁗ + O(h⁴), with, for ẍ = F(x, v),
///   x⁗ = F_xx v² + 2 F_xv v F + F_vv F² + F_x F + F_v F_x v + F_v² F
/// (the deterministic part; exact in expectation for drifts linear in v). F is a pilot drift
/// fit; polynomial terms and y|y| enter, sign(y) and u are left out.
class FourthDerivative {
 public:
  FourthDerivative() = default;
  FourthDerivative(const std::vector<Term>& terms, const Eigen::VectorXd& c, double h) : factor_(h * h / 12.0) {
    int px = 0, py = 0;
    for (const auto& t : terms)
      if (t.kind == TermKind::Monomial) px = std::max(px, t.px), py = std::max(py, t.py);
    F_.assign(static_cast<std::size_t>(py + 1), std::vector<double>(static_cast<std::size_t>(px + 1), 0.0));
    for (std::size_t k = 0; k < terms.size(); ++k) {
      const Term& t = terms[k];
      if (t.kind == TermKind::Monomial)
        F_[static_cast<std::size_t>(t.py)][static_cast<std::size_t>(t.px)] += c[static_cast<Eigen::Index>(k)];
      else if (t.kind == TermKind::YAbsY)
        yabsy_ += c[static_cast<Eigen::Index>(k)];
    }
    Fx_ = dx(F_);
    Fxx_ = dx(Fx_);
    Fv_ = dv(F_);
    Fxv_ = dx(Fv_);
    Fvv_ = dv(Fv_);
  }
  /// (h²/12)·x⁗ at (x, v).
  double operator()(double x, double v) const {
    const double sv = static_cast<double>((v > 0) - (v < 0));
    const double F = eval(F_, x, v) + yabsy_ * v * std::abs(v);
    const double Fx = eval(Fx_, x, v), Fxx = eval(Fxx_, x, v), Fxv = eval(Fxv_, x, v);
    const double Fv = eval(Fv_, x, v) + 2.0 * yabsy_ * std::abs(v);
    const double Fvv = eval(Fvv_, x, v) + 2.0 * yabsy_ * sv;
    return factor_ * (Fxx * v * v + 2.0 * Fxv * v * F + Fvv * F * F + Fx * F + Fv * Fx * v + Fv * Fv * F);
  }

 private:
  using Poly = std::vector<std::vector<double>>;  // a[py][px]
  static Poly dx(const Poly& a) {
    Poly d = a;
    for (auto& row : d) {
      for (std::size_t p = 0; p + 1 < row.size(); ++p) row[p] = row[p + 1] * static_cast<double>(p + 1);
      if (!row.empty()) row.back() = 0.0;
    }
    return d;
  }
  static Poly dv(const Poly& a) {
    Poly d(a.size(), std::vector<double>(a.empty() ? 0 : a[0].size(), 0.0));
    for (std::size_t q = 0; q + 1 < a.size(); ++q)
      for (std::size_t p = 0; p < a[q + 1].size(); ++p) d[q][p] = a[q + 1][p] * static_cast<double>(q + 1);
    return d;
  }
  static double eval(const Poly& a, double x, double v) {
    double s = 0.0;
    for (std::size_t q = a.size(); q-- > 0;) {
      double px = 0.0;
      for (std::size_t p = a[q].size(); p-- > 0;) px = px * x + a[q][p];
      s = s * v + px;
    }
    return s;
  }
  Poly F_, Fx_, Fxx_, Fv_, Fxv_, Fvv_;
  double yabsy_ = 0.0;
  double factor_ = 0.0;
};

}  // namespace vehs::identify::detail

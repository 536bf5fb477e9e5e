#include "vehs/core/diffusion_domain.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>

#include "vehs/core/detail/format.hpp"

namespace vehs {

namespace {

using Polynomial = std::map<int, double>;  ///< power of x -> coefficient (non-zero)

Polynomial at_rest(const Model& model) {
  Polynomial p;
  for (const auto& tc : model.diffusion)  // sign(y), y|y| and every y^k (k > 0) vanish at y = 0
    if (tc.term.kind == TermKind::Monomial && tc.term.py == 0) p[tc.term.px] += tc.coef;
  for (auto it = p.begin(); it != p.end();) it = it->second == 0.0 ? p.erase(it) : std::next(it);
  return p;
}

double value(const Polynomial& p, double x) {
  double s = 0.0;
  for (const auto& [k, c] : p) s += c * std::pow(x, k);
  return s;
}

std::string text(const Polynomial& p) {
  std::string s;
  for (const auto& [k, c] : p) {
    const std::string mag = detail::format_number(std::abs(c), 6);
    s += s.empty() ? (c < 0 ? "-" : "") : (c < 0 ? " - " : " + ");
    s += k == 0 ? mag : mag + "·x" + (k == 1 ? "" : "^" + std::to_string(k));
  }
  return s;
}

/// The |x| beyond which p is negative on the side `sign` (p negative at sign·R, R a root bound).
double crossing(const Polynomial& p, double sign, double R) {
  double lo = 0.0, hi = R;
  const int n = 4096;  // the last sign change on a fine scan, then bisection
  for (int i = n - 1; i >= 0; --i) {
    const double t = R * i / n;
    if (value(p, sign * t) >= 0.0) {
      lo = t;
      hi = R * (i + 1) / n;
      break;
    }
  }
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    (value(p, sign * mid) >= 0.0 ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

std::string diffusion_negative_at_large_x(const Model& model) {
  const Polynomial p = at_rest(model);
  if (p.empty()) return "";
  const int d = p.rbegin()->first;
  const double c = p.rbegin()->second;
  if (d % 2 == 0 && c > 0.0) return "";
  const std::string rate = " (a22 is a variance rate and must be >= 0)";
  if (d == 0) return "diffusion a22(x, 0) = " + detail::format_number(c, 6) + " is negative" + rate;
  double R = 1.0;  // Cauchy's bound on the roots
  for (const auto& [k, ck] : p)
    if (k < d) R = std::max(R, 1.0 + std::abs(ck / c));
  double at = R, at_sign = 1.0;
  for (double sign : {1.0, -1.0})
    if (value(p, sign * R) < 0.0)
      if (const double t = crossing(p, sign, R); t < at || sign > 0.0) at = t, at_sign = sign;
  const std::string where = d % 2 == 0 ? "|x| = " : (at_sign < 0.0 ? "x = -" : "x = ");
  return "diffusion a22(x, 0) = " + text(p) + " has leading term " + detail::format_number(c, 6) + "·x^" +
         std::to_string(d) + " and turns negative at " + where + detail::format_number(at, 4) + rate;
}

}  // namespace vehs

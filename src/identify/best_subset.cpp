#include "best_subset.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vehs::identify {

namespace {

constexpr double kMaxCondition = 1e12;  ///< as require_well_conditioned
constexpr double kMaxSubsets = 1e5;     ///< supports fitted at most (≈ 0.1 s)

/// C(n, 0) + … + C(n, m), saturating just above `cap`.
double subsets_up_to(int n, int m, double cap) {
  double total = 0.0, c = 1.0;
  for (int k = 0; k <= m && k <= n; ++k) {
    total += c;
    if (total > cap) return cap + 1.0;
    c = c * double(n - k) / double(k + 1);
  }
  return total;
}

double fit_bic(const QuadraticStats& total, const SupportFit& f, double variance_factor) {
  return f.condition < kMaxCondition ? bic(total.n, f.loss, f.support.size(), variance_factor)
                                     : std::numeric_limits<double>::quiet_NaN();
}

/// The lowest-BIC support among all that hold the kept terms and at most `m` free ones.
SupportFit exhaustive(const QuadraticStats& total, const std::vector<int>& kept, const std::vector<int>& free, int m,
                      double variance_factor, double& best_bic) {
  SupportFit best;
  best_bic = std::numeric_limits<double>::infinity();
  std::vector<int> pick;
  const int n = static_cast<int>(free.size());
  auto visit = [&](auto&& self, int from) -> void {  // combinations of `free` in index order
    std::vector<int> s = kept;
    s.insert(s.end(), pick.begin(), pick.end());
    std::sort(s.begin(), s.end());
    SupportFit f = fit_support(total, s);
    const double b = fit_bic(total, f, variance_factor);
    if (std::isfinite(b) && b < best_bic) best = std::move(f), best_bic = b;
    if (static_cast<int>(pick.size()) == m) return;
    for (int i = from; i < n; ++i) {
      pick.push_back(free[static_cast<std::size_t>(i)]);
      self(self, i + 1);
      pick.pop_back();
    }
  };
  visit(visit, 0);
  return best;
}

}  // namespace

double bic(double n, double loss, std::size_t terms, double variance_factor) {
  if (!(loss > 0.0) || !(n > 1.0)) return std::numeric_limits<double>::quiet_NaN();
  return n * std::log(loss / n) / variance_factor + static_cast<double>(terms) * std::log(n);
}

SupportFit bic_best_subset(const QuadraticStats& total, const SupportFit& start, const std::vector<int>& candidates,
                           const std::vector<bool>& keep, double variance_factor) {
  std::vector<int> kept, free;
  for (int c : candidates) (keep[static_cast<std::size_t>(c)] ? kept : free).push_back(c);
  int m = 1;  // one more free term than the path's choice, fewer when that is too many supports
  for (int t : start.support) m += !keep[static_cast<std::size_t>(t)];
  const int n = static_cast<int>(free.size());
  while (m > 0 && subsets_up_to(n, m, kMaxSubsets) > kMaxSubsets) --m;
  double best_bic = 0.0;
  SupportFit best = exhaustive(total, kept, free, m, variance_factor, best_bic);
  return std::isfinite(best_bic) && best_bic < fit_bic(total, start, variance_factor) ? best : start;
}

}  // namespace vehs::identify

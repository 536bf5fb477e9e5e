#include "bic_swaps.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vehs::identify {

namespace {

constexpr double kMaxCondition = 1e12;  ///< as require_well_conditioned
constexpr int kMaxMoves = 100;
constexpr double kMaxSubsets = 1e5;  ///< exhaustive search up to this many supports (≈ 0.1 s)

/// Every support one move away from `s`: one candidate added, one non-kept term removed, or one
/// non-kept term swapped for a candidate.
std::vector<std::vector<int>> neighbours(const std::vector<int>& s, const std::vector<int>& candidates,
                                         const std::vector<bool>& keep) {
  std::vector<int> out_of;
  for (int c : candidates)
    if (std::find(s.begin(), s.end(), c) == s.end()) out_of.push_back(c);
  std::vector<std::vector<int>> n;
  for (int c : out_of) {
    std::vector<int> t = s;
    t.push_back(c);
    std::sort(t.begin(), t.end());
    n.push_back(t);
  }
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (keep[static_cast<std::size_t>(s[i])]) continue;
    std::vector<int> t = s;
    t.erase(t.begin() + static_cast<long>(i));
    n.push_back(t);
    for (int c : out_of) {
      std::vector<int> u = t;
      u.push_back(c);
      std::sort(u.begin(), u.end());
      n.push_back(u);
    }
  }
  return n;
}

}  // namespace

double support_bic(const QuadraticStats& total, const SupportFit& fit, double variance_factor) {
  const double n = total.n, L = fit.loss;
  if (!(L > 0.0) || !(n > 1.0) || !(fit.condition < kMaxCondition)) return std::numeric_limits<double>::quiet_NaN();
  return n * std::log(L / n) / variance_factor + static_cast<double>(fit.support.size()) * std::log(n);
}

namespace {

/// C(n, 0) + … + C(n, m), saturating at `cap`.
double subsets_up_to(int n, int m, double cap) {
  double total = 0.0, c = 1.0;
  for (int k = 0; k <= m && k <= n; ++k) {
    total += c;
    if (total > cap) return cap + 1.0;
    c = c * double(n - k) / double(k + 1);
  }
  return total;
}

/// The lowest-BIC support among all that hold the kept terms and at most `m` others.
SupportFit exhaustive(const QuadraticStats& total, const std::vector<int>& kept, const std::vector<int>& free, int m,
                      double variance_factor, double& best_bic) {
  SupportFit best;
  best_bic = std::numeric_limits<double>::infinity();
  std::vector<int> pick;
  const int n = static_cast<int>(free.size());
  // depth-first over combinations of `free` in increasing index order
  auto visit = [&](auto&& self, int from) -> void {
    std::vector<int> s = kept;
    s.insert(s.end(), pick.begin(), pick.end());
    std::sort(s.begin(), s.end());
    SupportFit f = fit_support(total, s);
    const double b = support_bic(total, f, variance_factor);
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

SupportFit bic_best_subset(const QuadraticStats& total, const SupportFit& start, const std::vector<int>& candidates,
                           const std::vector<bool>& keep, double variance_factor) {
  std::vector<int> kept, free;
  for (int c : candidates) (keep[static_cast<std::size_t>(c)] ? kept : free).push_back(c);
  int m = 0;
  for (int t : start.support) m += !keep[static_cast<std::size_t>(t)];
  ++m;  // one more than the path's choice
  if (subsets_up_to(static_cast<int>(free.size()), m, kMaxSubsets) > kMaxSubsets)
    return bic_local_search(total, start, candidates, keep, variance_factor);
  double bic = 0.0;
  SupportFit best = exhaustive(total, kept, free, m, variance_factor, bic);
  const double start_bic = support_bic(total, start, variance_factor);
  return std::isfinite(bic) && !(bic >= start_bic) ? best : start;
}

SupportFit bic_local_search(const QuadraticStats& total, const SupportFit& start, const std::vector<int>& candidates,
                            const std::vector<bool>& keep, double variance_factor) {
  SupportFit best = start;
  std::sort(best.support.begin(), best.support.end());
  best = fit_support(total, best.support);
  double best_bic = support_bic(total, best, variance_factor);
  if (!std::isfinite(best_bic)) return start;
  for (int move = 0; move < kMaxMoves; ++move) {
    SupportFit next;
    double next_bic = best_bic;
    for (const auto& s : neighbours(best.support, candidates, keep)) {
      SupportFit f = fit_support(total, s);
      const double b = support_bic(total, f, variance_factor);
      if (std::isfinite(b) && b < next_bic - 1e-9) next = std::move(f), next_bic = b;
    }
    if (!(next_bic < best_bic)) break;
    best = std::move(next);
    best_bic = next_bic;
  }
  return best;
}

}  // namespace vehs::identify

#include "vehs/core/detail/stepped_runs.hpp"

#include <algorithm>
#include <cmath>

namespace vehs::detail {

namespace {

constexpr double kStepOverNeighbours = 4.0;  ///< the entering or leaving step over the largest increment around
constexpr double kGridSteps = 3.0;           ///< and over this many grid steps
constexpr std::size_t kMinWindow = 16;

/// The smallest non-zero |x[i+1] − x[i]| of the record (its grid step when quantised).
double grid_step(const double* x, std::size_t n) {
  double q = 0.0;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double d = std::abs(x[i + 1] - x[i]);
    if (d > 0.0 && (q == 0.0 || d < q)) q = d;
  }
  return q;
}

/// The largest |x[k+1] − x[k]| for k in [from, to).
double largest_increment(const double* x, std::size_t from, std::size_t to) {
  double m = 0.0;
  for (std::size_t k = from; k < to; ++k) m = std::max(m, std::abs(x[k + 1] - x[k]));
  return m;
}

}  // namespace

void append_stepped_runs(const double* x, std::size_t n, std::size_t record, std::size_t first_line,
                         std::size_t min_run, const std::vector<double>& skip, std::vector<FlatStretch>& out) {
  const double q = grid_step(x, n);
  if (!(q > 0.0)) return;
  std::size_t previous = 0;  // the length of the run before
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i + 1;
    while (j < n && x[j] == x[i]) ++j;
    const std::size_t L = j - i;
    std::size_t next = 0;
    while (j + next < n && x[j + next] == x[j]) ++next;
    if (L >= min_run && std::find(skip.begin(), skip.end(), x[i]) == skip.end()) {
      const std::size_t w = std::max(L, kMinWindow);
      // increments around the run: [i−1−w, i−1) before (the step into it, x[i]−x[i−1], left out)
      // and [j, j+w) after (the step out of it, x[j]−x[j−1], left out)
      double around = 0.0;
      if (i >= 2) around = largest_increment(x, i >= w + 1 ? i - 1 - w : 0, i - 1);
      if (j + 1 < n) around = std::max(around, largest_increment(x, j, std::min(n - 1, j + w)));
      // a step between two runs is the longer one's (a dropout's, not the natural run beside it)
      const bool own_into = i > 0 && !(previous >= min_run && previous > L);
      const bool own_out = j < n && !(next >= min_run && next > L);
      const double into = own_into ? std::abs(x[i] - x[i - 1]) : 0.0;
      const double out_of = own_out ? std::abs(x[j] - x[j - 1]) : 0.0;
      const double bar = std::max(kStepOverNeighbours * around, kGridSteps * q);
      if (std::max(into, out_of) > bar) out.push_back({record, i, L, first_line + i, x[i]});
    }
    previous = L;
    i = j;
  }
}

}  // namespace vehs::detail

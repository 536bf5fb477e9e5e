#include "vehs/core/detail/clipped_runs.hpp"

#include <algorithm>
#include <limits>

namespace vehs::detail {

namespace {

constexpr double kPileUp = 3.0;         ///< extreme level's samples over the next level's
constexpr std::size_t kExcess = 30;     ///< and this many more
constexpr std::size_t kMinRuns = 3;     ///< separate visits
constexpr double kLongRun = 3.0;        ///< or one run this many times the longest elsewhere

/// The longest run of one value at `level`, and at any value but the record's two extremes (the
/// other may be clipped too).
void longest_runs(const double* x, std::size_t n, double level, double lo, double hi, std::size_t& at_level,
                  std::size_t& elsewhere) {
  at_level = elsewhere = 0;
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i + 1;
    while (j < n && x[j] == x[i]) ++j;
    if (x[i] == level) at_level = std::max(at_level, j - i);
    else if (x[i] != lo && x[i] != hi) elsewhere = std::max(elsewhere, j - i);
    i = j;
  }
}

/// The runs at `level` when it is piled up against `inner` (the next value inwards), in several
/// runs or in one much longer than any run at another value (a single clipped excursion: 221
/// samples at the extreme of a 16-bit record whose other runs are a few samples).
void runs_if_piled(const double* x, std::size_t n, double level, double inner, double lo, double hi,
                   std::size_t record, std::size_t first_line, std::vector<FlatStretch>& out) {
  std::size_t at = 0, next = 0, runs = 0;
  for (std::size_t i = 0; i < n; ++i) {
    at += x[i] == level;
    next += x[i] == inner;
    runs += x[i] == level && (i == 0 || x[i - 1] != level);
  }
  if (double(at) <= kPileUp * double(next) + double(kExcess)) return;
  std::size_t longest = 0, other = 0;
  if (runs < kMinRuns) longest_runs(x, n, level, lo, hi, longest, other);
  if (runs < kMinRuns && !(double(longest) > kLongRun * double(other))) return;
  for (std::size_t i = 0; i < n;) {
    if (x[i] != level) {
      ++i;
      continue;
    }
    std::size_t j = i + 1;
    while (j < n && x[j] == level) ++j;
    out.push_back({record, i, j - i, first_line + i, level, true});
    i = j;
  }
}

}  // namespace

void append_clipped_runs(const double* x, std::size_t n, std::size_t record, std::size_t first_line,
                         std::vector<FlatStretch>& out) {
  if (n == 0) return;
  const double hi = *std::max_element(x, x + n), lo = *std::min_element(x, x + n);
  double below_hi = -std::numeric_limits<double>::infinity(), above_lo = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    if (x[i] < hi) below_hi = std::max(below_hi, x[i]);
    if (x[i] > lo) above_lo = std::min(above_lo, x[i]);
  }
  runs_if_piled(x, n, lo, above_lo, lo, hi, record, first_line, out);
  runs_if_piled(x, n, hi, below_hi, lo, hi, record, first_line, out);
}

}  // namespace vehs::detail

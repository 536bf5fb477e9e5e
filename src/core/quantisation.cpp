#include "vehs/core/quantisation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace vehs {

namespace {

constexpr double kOffGrid = 1e-3;        ///< largest |x/q − round(x/q)| on the grid
constexpr double kRepeatShare = 0.125;   ///< values repeated at least this often: quantised
constexpr double kStepShare = 0.25;      ///< neighbouring levels at least this often one step apart
constexpr std::size_t kMaxLook = 1u << 20;  ///< values sorted to find the step

/// The smallest positive spacing between the distinct values of every record's first samples,
/// the share of those values that repeat, and the share of the spacings within 1e-3 of the
/// smallest (a grid's step is the spacing of most neighbouring levels; one stray value makes a
/// smaller spacing once).
double smallest_spacing(const Dataset& data, double& repeated, double& at_step) {
  std::vector<double> v, gaps;
  double best = 0.0;
  std::size_t looked = 0, distinct = 0;
  const std::size_t per_record = std::max<std::size_t>(kMaxLook / std::max<std::size_t>(data.records.size(), 1), 64);
  for (const Record& rec : data.records) {
    if (rec.size == 0) continue;
    const double* x = data.x_of(rec);
    v.assign(x, x + std::min(rec.size, per_record));
    std::sort(v.begin(), v.end());
    const double tiny = 1e-12 * std::max(std::abs(v.front()), std::abs(v.back()));
    looked += v.size();
    ++distinct;
    for (std::size_t i = 1; i < v.size(); ++i) {
      const double d = v[i] - v[i - 1];
      if (d <= tiny) continue;
      ++distinct;
      gaps.push_back(d);
      if (best == 0.0 || d < best) best = d;
    }
  }
  repeated = looked > 0 ? 1.0 - double(distinct) / double(looked) : 0.0;
  const auto near = std::count_if(gaps.begin(), gaps.end(), [&](double d) { return d <= best * (1.0 + kOffGrid); });
  at_step = gaps.empty() ? 0.0 : double(near) / double(gaps.size());
  return best;
}

/// Whether every value of every record is on the grid of step q from the record's smallest value.
bool on_grid(const Dataset& data, double q) {
  for (const Record& rec : data.records) {
    const double* x = data.x_of(rec);
    if (rec.size == 0) continue;
    const double x0 = *std::min_element(x, x + rec.size);
    for (std::size_t i = 0; i < rec.size; ++i) {
      const double m = (x[i] - x0) / q;
      if (!(std::abs(m - std::round(m)) <= kOffGrid)) return false;
    }
  }
  return true;
}

/// The stride from which increments spread over at least q (doubling; capped by the records).
int dither_stride(const Dataset& data, double q) {
  std::size_t shortest = data.records.front().size;
  for (const Record& rec : data.records) shortest = std::min(shortest, rec.size);
  int k = 1;
  for (; 8 * static_cast<std::size_t>(k) < shortest; k *= 2) {
    double s2 = 0.0, n = 0.0;
    for (const Record& rec : data.records) {
      const double* x = data.x_of(rec);
      const std::size_t m = std::min(rec.size, kMaxLook / std::max<std::size_t>(data.records.size(), 1) + k);
      for (std::size_t i = 0; i + k < m; ++i) s2 += (x[i + k] - x[i]) * (x[i + k] - x[i]), n += 1.0;
    }
    if (n > 0 && s2 / n >= q * q) break;
  }
  return k;
}

/// The spacing of two parsed values carries their round-off (0.99999999999989 for counts,
/// 0.000999999999999 for "%.3f" values near 3.7): the value with the fewest significant digits
/// within 1e-9 of it (a scaled count such as 20/2^24 keeps its digits).
double shortest_near(double g) {
  char buf[32];
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, g);
    const double v = std::strtod(buf, nullptr);
    if (std::abs(v - g) <= 1e-9 * g) return v;
  }
  return g;
}

}  // namespace

Quantisation find_quantisation(const Dataset& data) {
  Quantisation out;
  if (data.records.empty()) return out;
  double repeated = 0.0, at_step = 0.0;
  const double g = smallest_spacing(data, repeated, at_step);
  if (!(g > 0.0) || repeated < kRepeatShare || at_step < kStepShare || !on_grid(data, g)) return out;
  out.step = shortest_near(g);
  out.dither_stride = dither_stride(data, out.step);
  return out;
}

}  // namespace vehs

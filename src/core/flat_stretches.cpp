#include "vehs/core/flat_stretches.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "vehs/core/detail/clipped_runs.hpp"
#include "vehs/core/detail/stepped_runs.hpp"
#include "vehs/core/drop_samples.hpp"

namespace vehs {

namespace {

constexpr std::size_t kMinRun = 5;
/// A record with this share of its consecutive pairs repeated inside short runs is quantised:
/// its values repeat legitimately, in long runs at its turning points, so it is not checked.
constexpr double kQuantisedShare = 1e-3;
/// ... or with most of its consecutive pairs equal (a noise-free ADC sampled far faster than the
/// signal moves: every repeat in a long run, 481 samples at a 10-bit bistable's turning point).
constexpr double kMostlyEqual = 0.5;
constexpr double kFalseAlarm = 1e-9;  ///< per record, under independent repeats

/// The shortest run flagged in a record of n samples with `equal` equal consecutive pairs.
std::size_t flagged_run(std::size_t n, std::size_t equal) {
  const double N = static_cast<double>(n);
  const double p = std::clamp(static_cast<double>(equal) / std::max(N - 1.0, 1.0), 1.0 / N, 1.0 - 1e-12);
  const double L = 1.0 + std::log(kFalseAlarm / N) / std::log(p);  // N p^(L−1) = kFalseAlarm
  return std::max(kMinRun, static_cast<std::size_t>(std::ceil(L)));
}

/// The runs of one record longer than its own repeats explain, not at a clipped level (already
/// flagged, every run there).
void append_long_runs(const double* x, const Record& rec, std::size_t k, std::size_t equal,
                      const std::vector<double>& clipped_levels, std::vector<FlatStretch>& out) {
  const auto at_clip = [&](double v) {
    return std::find(clipped_levels.begin(), clipped_levels.end(), v) != clipped_levels.end();
  };
  const std::size_t bar = flagged_run(rec.size, equal);
  for (std::size_t i = 0; i < rec.size;) {  // a second pass: storing the candidates would cost memory on quantised data
    std::size_t j = i + 1;
    while (j < rec.size && x[j] == x[i]) ++j;
    if (j - i >= bar && !at_clip(x[i])) out.push_back({k, i, j - i, rec.first_line + i, x[i]});
    i = j;
  }
}

}  // namespace

std::vector<FlatStretch> find_flat_stretches(const Dataset& data) {
  std::vector<FlatStretch> out;
  for (std::size_t k = 0; k < data.records.size(); ++k) {
    const Record& rec = data.records[k];
    if (rec.size < kMinRun) continue;
    const double* x = data.x_of(rec);
    std::size_t equal = 0, in_short_runs = 0;  // equal pairs; those inside runs shorter than kMinRun
    for (std::size_t i = 0; i < rec.size;) {
      std::size_t j = i + 1;
      while (j < rec.size && x[j] == x[i]) ++j;
      equal += j - i - 1;
      if (j - i < kMinRun) in_short_runs += j - i - 1;
      i = j;
    }
    if (equal + 1 < kMinRun) continue;
    std::vector<FlatStretch> found;
    detail::append_clipped_runs(x, rec.size, k, rec.first_line, found);
    std::vector<double> levels;  // the clipped levels: every run there is flagged already
    for (const FlatStretch& f : found)
      if (std::find(levels.begin(), levels.end(), f.x) == levels.end()) levels.push_back(f.x);
    const double pairs = double(rec.size - 1);
    if (double(in_short_runs) < kQuantisedShare * pairs && double(equal) < kMostlyEqual * pairs)
      append_long_runs(x, rec, k, equal, levels, found);
    else  // quantised: runs entered or left by a jump (dropouts, held readings)
      detail::append_stepped_runs(x, rec.size, k, rec.first_line, kMinRun, levels, found);
    std::sort(found.begin(), found.end(), [](const FlatStretch& a, const FlatStretch& b) { return a.sample < b.sample; });
    out.insert(out.end(), found.begin(), found.end());
  }
  return out;
}

std::string describe_flat_stretches(const Dataset& data, const std::vector<FlatStretch>& stretches,
                                    std::size_t max_listed) {
  std::string s;
  for (std::size_t g = 0; g < stretches.size() && g < max_listed; ++g) {
    const FlatStretch& f = stretches[g];
    char buf[160];
    std::snprintf(buf, sizeof buf, "lines %zu-%zu (%zu samples of x = %.6g%s)", f.line, f.line + f.length - 1, f.length,
                  f.x, f.clipped ? ", the record's extreme value, piled up: clipped?" : "");
    const std::string& source = data.records[f.record].source;
    s += (g == 0 ? "" : ", ") +
         (g == 0 || source != data.records[stretches[g - 1].record].source ? source + ": " : "") + buf;
  }
  if (stretches.size() > max_listed) s += " and " + std::to_string(stretches.size() - max_listed) + " more";
  return s;
}

Dataset drop_flat_stretches(const Dataset& data, const std::vector<FlatStretch>& stretches, std::size_t min_samples) {
  std::vector<SampleRef> removed;
  for (const FlatStretch& f : stretches)
    for (std::size_t i = 0; i < f.length; ++i) removed.push_back({f.record, f.sample + i});
  return drop_samples(data, removed, min_samples);
}

}  // namespace vehs

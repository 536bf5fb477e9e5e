// The residual-lines test of a diagnosis: the largest excess of the residual spectrum in ONE
// frequency bin (a periodic force the model lacks is a line that log-spaced bands dilute). Per
// bin k, the paired t statistic over units of log P_data minus the twins' mean of log P_twin; the
// largest t is referred to the one-sided t law with U − 1 degrees of freedom, Bonferroni over the
// bins.
#include <cmath>
#include <limits>
#include <sstream>

#include "comparison.hpp"
#include "unit_math.hpp"
#include "vehs/diagnose/distributions.hpp"

namespace vehs::diagnose::detail {

Component residual_line_test(const Comparison& cmp) {
  const StatsSetup& setup = cmp.setup;
  const std::vector<UnitStats>& dstats = cmp.data_stats;
  const std::vector<UnitStats>& tstats = cmp.twin_stats;
  const auto Ud = static_cast<std::size_t>(cmp.units());
  const double dt = setup.dt;
  Component c{"residual_lines",
              "largest excess of the whitened-residual spectrum in a single frequency bin (periodic forcing)",
              TestResult{}};
  const std::size_t K = setup.seg_r / 2 + 1;
  double best = -std::numeric_limits<double>::infinity();
  std::size_t kbest = 0;
  int used = 0, units_used = 0;
  for (std::size_t k = 1; k < K; ++k) {
    double s1 = 0.0, s2 = 0.0;
    int n = 0;
    for (std::size_t j = 0; j < Ud; ++j) {
      const auto& a = dstats[j];
      const auto& b = tstats[j];
      if (k >= a.rpsd.size() || k >= b.rpsd.size()) continue;
      // mean of the replicates' logs on both sides (unit_stats.hpp: a log of a mean is biased)
      const double d = mean_log_band(a.rpsd_each, k, k + 1) - mean_log_band(b.rpsd_each, k, k + 1);
      if (!std::isfinite(d)) continue;
      s1 += d;
      s2 += d * d;
      ++n;
    }
    if (n < 3) continue;
    const double m = s1 / n, var = (s2 - n * m * m) / (n - 1.0);
    if (!(var > 0.0)) continue;
    const double tk = m / std::sqrt(var / n);
    ++used;
    units_used = std::max(units_used, n);
    if (tk > best) best = tk, kbest = k;
  }
  if (used > 0) {
    const double nu = units_used - 1.0;
    const double p1 = best > 0 ? 0.5 * t_sf_two_sided(best, nu) : 1.0 - 0.5 * t_sf_two_sided(best, nu);
    TestResult& t = c.test;
    t.available = true;
    t.units = units_used;
    t.statistic = best;
    t.dof = 1.0;
    t.p_value = std::min(1.0, p1 * used);
    t.chi2 = chi2_equivalent(t.p_value, 1.0, best * best);
    const double f = static_cast<double>(kbest) / (static_cast<double>(setup.seg_r) * dt);
    std::ostringstream os;
    os << "largest paired t of log residual spectrum = " << best << " at frequency " << f << " (angular "
       << 2.0 * M_PI * f << ", bin width " << 1.0 / (static_cast<double>(setup.seg_r) * dt) << ") over " << used
       << " bins, one-sided t(" << nu << "), Bonferroni";
    t.method = os.str();
    finish_excess(t);
  } else {
    c.test.note = "no frequency bin with enough units";
  }
  return c;
}

}  // namespace vehs::diagnose::detail

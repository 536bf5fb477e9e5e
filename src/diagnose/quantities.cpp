// The quantities of a diagnosis's table: E[X²], E[v̂²], well probabilities and the well-to-well
// transition rate of the data and the twins, with a paired jackknife z of their difference.
#include <cmath>
#include <numeric>

#include "comparison.hpp"
#include "unit_math.hpp"

namespace vehs::diagnose::detail {

void add_quantities(const Comparison& cmp, Result& res) {
  const StatsSetup& setup = cmp.setup;
  const std::vector<UnitStats>& dstats = cmp.data_stats;
  const std::vector<UnitStats>& tstats = cmp.twin_stats;
  const auto Ud = static_cast<std::size_t>(cmp.units());
  const int W = setup.wells() >= 2 ? setup.wells() : 0;
  std::vector<double> nd(Ud), nt(Ud), xd(Ud), xt(Ud), vd(Ud), vt(Ud);
  for (std::size_t j = 0; j < Ud; ++j) {
    nd[j] = rows_of(dstats[j]);
    nt[j] = rows_of(tstats[j]);
    xd[j] = dstats[j].sx2, xt[j] = tstats[j].sx2, vd[j] = dstats[j].sv2, vt[j] = tstats[j].sv2;
  }
  auto quantity = [&](const std::string& name, const std::vector<double>& Nd, const std::vector<double>& Dd,
                      const std::vector<double>& Nt, const std::vector<double>& Dt) {
    Quantity q;
    q.name = name;
    const Ratio a = ratio_over_units(Nd, Dd), b = ratio_over_units(Nt, Dt);
    q.data = a.value, q.data_se = a.se, q.twin = b.value, q.twin_se = b.se;
    // paired jackknife z of the difference (unit-to-unit spread only)
    const double SNd = std::accumulate(Nd.begin(), Nd.end(), 0.0), SDd = std::accumulate(Dd.begin(), Dd.end(), 0.0);
    const double SNt = std::accumulate(Nt.begin(), Nt.end(), 0.0), SDt = std::accumulate(Dt.begin(), Dt.end(), 0.0);
    std::vector<double> jk(Nd.size());
    double mean = 0.0;
    for (std::size_t j = 0; j < Nd.size(); ++j) {
      jk[j] = (SNd - Nd[j]) / (SDd - Dd[j]) - (SNt - Nt[j]) / (SDt - Dt[j]);
      mean += jk[j];
    }
    mean /= static_cast<double>(Nd.size());
    double ss = 0.0;
    for (double v : jk) ss += (v - mean) * (v - mean);
    const double n = static_cast<double>(Nd.size());
    const double se = std::sqrt((n - 1.0) / n * ss);
    q.z = se > 0 ? (q.data - q.twin) / se : 0.0;
    res.quantities.push_back(q);
  };
  quantity("E[X^2]", xd, nd, xt, nt);
  quantity("E[v^2]", vd, nd, vt, nt);
  if (W >= 2) {
    std::vector<double> wd(Ud), wt(Ud), trd(Ud), trt(Ud), dud(Ud), dut(Ud);
    for (int w = 0; w < W; ++w) {
      for (std::size_t j = 0; j < Ud; ++j) {
        wd[j] = dstats[j].well_rows[static_cast<std::size_t>(w)];
        wt[j] = tstats[j].well_rows[static_cast<std::size_t>(w)];
      }
      quantity("P(well " + std::to_string(w + 1) + ", x_min = " + fmt(res.wells[static_cast<std::size_t>(w)].x_min, 3) + ")",
               wd, nd, wt, nt);
    }
    for (std::size_t j = 0; j < Ud; ++j) {
      trd[j] = dstats[j].transitions, trt[j] = tstats[j].transitions;
      dud[j] = dstats[j].duration, dut[j] = tstats[j].duration;
    }
    quantity("transition rate (per time unit)", trd, dud, trt, dut);
  }
}

}  // namespace vehs::diagnose::detail

// The one-step map of a diagnosis: the whitened residual's mean, log-variance and kurtosis per
// (x, v̂) bin, data vs twins, with paired delete-one-unit jackknife standard errors; the test
// combines the bins' t statistics (combine_t).
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "comparison.hpp"
#include "unit_math.hpp"

namespace vehs::diagnose::detail {

Component one_step_test(const Comparison& cmp, OneStepMap& map) {
  const Options& opt = cmp.options;
  const StatsSetup& setup = cmp.setup;
  const std::vector<UnitStats>& dstats = cmp.data_stats;
  const std::vector<UnitStats>& tstats = cmp.twin_stats;
  const int U = cmp.units();
  const auto Ud = static_cast<std::size_t>(U);
  const int R = cmp.replicates;
  OneStepMap& mp = map;
  mp.nx = setup.nx;
  mp.nv = setup.nv;
  mp.x_lo = setup.x_lo;
  mp.x_hi = setup.x_hi;
  mp.v_lo = setup.v_lo;
  mp.v_hi = setup.v_hi;
  const int B = setup.map_bins();
  mp.bins.resize(static_cast<std::size_t>(B));
  std::vector<double> tvals, nus;
  struct Mom {
    double n, m, var, kurt;
  };
  auto moments = [](const double* s) {
    Mom o{s[0], 0, 0, 0};
    if (s[0] <= 0) return o;
    const double m = s[1] / s[0], e2 = s[2] / s[0], e3 = s[3] / s[0], e4 = s[4] / s[0];
    o.m = m;
    o.var = e2 - m * m;
    const double m4 = e4 - 4 * m * e3 + 6 * m * m * e2 - 3 * m * m * m * m;
    o.kurt = o.var > 0 ? m4 / (o.var * o.var) : 0.0;
    return o;
  };
  for (int b = 0; b < B; ++b) {
    double D[5] = {0, 0, 0, 0, 0}, T[5] = {0, 0, 0, 0, 0};
    int ud = 0, ut = 0;
    for (std::size_t j = 0; j < Ud; ++j) {
      const double* d = dstats[j].map.data() + b * 5;
      const double* t = tstats[j].map.data() + b * 5;
      for (int k = 0; k < 5; ++k) D[k] += d[k], T[k] += t[k];
      ud += d[0] > 0;
      ut += t[0] > 0;
    }
    MapBin& mb = mp.bins[static_cast<std::size_t>(b)];
    const int i = b / setup.nv, jv = b % setup.nv;
    mb.x = setup.x_lo + (i + 0.5) * (setup.x_hi - setup.x_lo) / setup.nx;
    mb.v = setup.v_lo + (jv + 0.5) * (setup.v_hi - setup.v_lo) / setup.nv;
    const Mom md = moments(D), mt = moments(T);
    mb.n_data = md.n;
    mb.n_twin = mt.n / R;
    mb.mean_data = md.m;
    mb.mean_twin = mt.m;
    mb.var_data = md.var;
    mb.var_twin = mt.var;
    mb.kurt_data = md.kurt;
    mb.kurt_twin = mt.kurt;
    if (md.n < opt.min_bin_count || mt.n / R < opt.min_bin_count || ud < 2 || ut < 2 || U < 3) continue;
    const double th[3] = {md.m - mt.m, std::log(md.var / mt.var), md.kurt - mt.kurt};
    double acc[3] = {0, 0, 0}, acc2[3] = {0, 0, 0};
    std::vector<double> jk(3 * Ud);
    for (std::size_t j = 0; j < Ud; ++j) {
      double Dj[5], Tj[5];
      const double* d = dstats[j].map.data() + b * 5;
      const double* t = tstats[j].map.data() + b * 5;
      for (int k = 0; k < 5; ++k) Dj[k] = D[k] - d[k], Tj[k] = T[k] - t[k];
      const Mom a = moments(Dj), c = moments(Tj);
      const double v[3] = {a.m - c.m, (a.var > 0 && c.var > 0) ? std::log(a.var / c.var) : th[1], a.kurt - c.kurt};
      for (int k = 0; k < 3; ++k) {
        jk[3 * j + static_cast<std::size_t>(k)] = v[k];
        acc[k] += v[k];
      }
    }
    for (int k = 0; k < 3; ++k) {
      const double mean = acc[k] / static_cast<double>(Ud);
      for (std::size_t j = 0; j < Ud; ++j) {
        const double e = jk[3 * j + static_cast<std::size_t>(k)] - mean;
        acc2[k] += e * e;
      }
    }
    double z[3];
    for (int k = 0; k < 3; ++k) {
      const double se = std::sqrt((static_cast<double>(Ud) - 1.0) / static_cast<double>(Ud) * acc2[k]);
      z[k] = se > 0 ? th[k] / se : 0.0;
    }
    mb.z_mean = z[0];
    mb.z_var = z[1];
    mb.z_kurt = z[2];
    mb.used = true;
    tvals.push_back(z[0]);
    tvals.push_back(z[1]);
    nus.push_back(U - 1.0);
    nus.push_back(U - 1.0);
  }
  Component c{"one_step",
              "whitened one-step residual mean and log-variance per (x, v) bin, data vs twins",
              combine_t(tvals, nus)};
  if (!c.test.available) c.test.note = "no bin has " + fmt(opt.min_bin_count) + " rows on both sides";
  std::vector<int> idx;
  for (int b = 0; b < B; ++b)
    if (mp.bins[static_cast<std::size_t>(b)].used) idx.push_back(b);
  std::sort(idx.begin(), idx.end(), [&](int a, int b) {
    return std::abs(mp.bins[static_cast<std::size_t>(a)].z_mean) > std::abs(mp.bins[static_cast<std::size_t>(b)].z_mean);
  });
  if (idx.size() > 10) idx.resize(10);
  mp.worst = idx;
  auto profile = [&](bool over_v, bool mean_z) {
    const int n = over_v ? setup.nv : setup.nx;
    std::vector<double> s2(static_cast<std::size_t>(n), 0.0), cnt(static_cast<std::size_t>(n), 0.0);
    for (int b = 0; b < B; ++b) {
      const MapBin& mb = mp.bins[static_cast<std::size_t>(b)];
      if (!mb.used) continue;
      const auto k = static_cast<std::size_t>(over_v ? b % setup.nv : b / setup.nv);
      const double z = mean_z ? mb.z_mean : mb.z_var;
      s2[k] += z * z;
      cnt[k] += 1.0;
    }
    for (std::size_t k = 0; k < s2.size(); ++k)
      s2[k] = cnt[k] > 0 ? s2[k] / cnt[k] : std::numeric_limits<double>::quiet_NaN();
    return s2;
  };
  mp.v_profile_mean = profile(true, true);
  mp.v_profile_var = profile(true, false);
  mp.x_profile_mean = profile(false, true);
  mp.x_profile_var = profile(false, false);
  return c;
}

}  // namespace vehs::diagnose::detail

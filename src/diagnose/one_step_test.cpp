// The one-step map of a diagnosis: the whitened residual's mean, log-variance and kurtosis per
// (x, v̂) bin, data vs twins, with paired delete-one-unit jackknife standard errors; the test
// combines the bins' t statistics (combine_t).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "comparison.hpp"
#include "unit_math.hpp"

namespace vehs::diagnose::detail {

namespace {

/// Count, mean, variance and kurtosis from the power sums (n, Σr, Σr², Σr³, Σr⁴) of a bin.
struct BinMoments {
  double n = 0, m = 0, var = 0, kurt = 0;
};

BinMoments bin_moments(const double* s) {
  BinMoments o{s[0], 0, 0, 0};
  if (s[0] <= 0) return o;
  const double m = s[1] / s[0], e2 = s[2] / s[0], e3 = s[3] / s[0], e4 = s[4] / s[0];
  o.m = m;
  o.var = e2 - m * m;
  const double m4 = e4 - 4 * m * e3 + 6 * m * m * e2 - 3 * m * m * m * m;
  o.kurt = o.var > 0 ? m4 / (o.var * o.var) : 0.0;
  return o;
}

/// Bin b's power sums over all units, and how many units have rows in it.
void bin_sums(const std::vector<UnitStats>& stats, int b, double sums[5], int& units) {
  units = 0;
  for (int k = 0; k < 5; ++k) sums[k] = 0.0;
  for (const auto& u : stats) {
    const double* d = u.map.data() + b * 5;
    for (int k = 0; k < 5; ++k) sums[k] += d[k];
    units += d[0] > 0;
  }
}

/// Kish's effective number of units in bin b, (Σ w)²/Σ w² with w a unit's rows there (data plus
/// twins per replicate): the jackknife over units has about this many non-trivial terms. Short
/// records each visit a small part of (x, v̂), so a bin can hold rows of a few units only; its
/// t statistic then has a few degrees of freedom, not units − 1 (with units − 1 the true model
/// failed on 40 records of 2 time units, issue 13).
double effective_units(const Comparison& cmp, int b) {
  double s = 0.0, s2 = 0.0;
  for (std::size_t j = 0; j < cmp.data_stats.size(); ++j) {
    const double w = cmp.data_stats[j].map[static_cast<std::size_t>(b) * 5] +
                     cmp.twin_stats[j].map[static_cast<std::size_t>(b) * 5] / cmp.replicates;
    s += w;
    s2 += w * w;
  }
  return s2 > 0.0 ? s * s / s2 : 0.0;
}

/// z of the data − twin differences (mean, log-variance, kurtosis) of bin b, with paired
/// delete-one-unit jackknife standard errors.
std::array<double, 3> bin_z(const Comparison& cmp, int b, const double D[5], const double T[5], const BinMoments& md,
                            const BinMoments& mt) {
  const std::size_t U = static_cast<std::size_t>(cmp.units());
  const double th[3] = {md.m - mt.m, std::log(md.var / mt.var), md.kurt - mt.kurt};
  double acc[3] = {0, 0, 0}, acc2[3] = {0, 0, 0};
  std::vector<double> jk(3 * U);
  for (std::size_t j = 0; j < U; ++j) {
    double Dj[5], Tj[5];
    const double* d = cmp.data_stats[j].map.data() + b * 5;
    const double* t = cmp.twin_stats[j].map.data() + b * 5;
    for (int k = 0; k < 5; ++k) Dj[k] = D[k] - d[k], Tj[k] = T[k] - t[k];
    const BinMoments a = bin_moments(Dj), c = bin_moments(Tj);
    const double v[3] = {a.m - c.m, (a.var > 0 && c.var > 0) ? std::log(a.var / c.var) : th[1], a.kurt - c.kurt};
    for (int k = 0; k < 3; ++k) {
      jk[3 * j + static_cast<std::size_t>(k)] = v[k];
      acc[k] += v[k];
    }
  }
  for (int k = 0; k < 3; ++k) {
    const double mean = acc[k] / static_cast<double>(U);
    for (std::size_t j = 0; j < U; ++j) {
      const double e = jk[3 * j + static_cast<std::size_t>(k)] - mean;
      acc2[k] += e * e;
    }
  }
  std::array<double, 3> z{};
  for (int k = 0; k < 3; ++k) {
    const double se = std::sqrt((static_cast<double>(U) - 1.0) / static_cast<double>(U) * acc2[k]);
    z[static_cast<std::size_t>(k)] = se > 0 ? th[k] / se : 0.0;
  }
  return z;
}

/// The ten used bins with the largest |z| of the mean.
std::vector<int> worst_bins(const OneStepMap& mp) {
  std::vector<int> idx;
  for (int b = 0; b < static_cast<int>(mp.bins.size()); ++b)
    if (mp.bins[static_cast<std::size_t>(b)].used) idx.push_back(b);
  std::sort(idx.begin(), idx.end(), [&](int a, int b) {
    return std::abs(mp.bins[static_cast<std::size_t>(a)].z_mean) > std::abs(mp.bins[static_cast<std::size_t>(b)].z_mean);
  });
  if (idx.size() > 10) idx.resize(10);
  return idx;
}

/// Mean z² of the used bins per v̂ column (over_v) or x row, of the mean or the variance z.
std::vector<double> z2_profile(const OneStepMap& mp, bool over_v, bool mean_z) {
  const int n = over_v ? mp.nv : mp.nx;
  std::vector<double> s2(static_cast<std::size_t>(n), 0.0), cnt(static_cast<std::size_t>(n), 0.0);
  for (int b = 0; b < static_cast<int>(mp.bins.size()); ++b) {
    const MapBin& mb = mp.bins[static_cast<std::size_t>(b)];
    if (!mb.used) continue;
    const auto k = static_cast<std::size_t>(over_v ? b % mp.nv : b / mp.nv);
    const double z = mean_z ? mb.z_mean : mb.z_var;
    s2[k] += z * z;
    cnt[k] += 1.0;
  }
  for (std::size_t k = 0; k < s2.size(); ++k) s2[k] = cnt[k] > 0 ? s2[k] / cnt[k] : std::numeric_limits<double>::quiet_NaN();
  return s2;
}

}  // namespace

Component one_step_test(const Comparison& cmp, OneStepMap& mp) {
  const Options& opt = cmp.options;
  const StatsSetup& setup = cmp.setup;
  const int U = cmp.units();
  const int R = cmp.replicates;
  mp.nx = setup.nx;
  mp.nv = setup.nv;
  mp.x_lo = setup.x_lo;
  mp.x_hi = setup.x_hi;
  mp.v_lo = setup.v_lo;
  mp.v_hi = setup.v_hi;
  const int B = setup.map_bins();
  mp.bins.resize(static_cast<std::size_t>(B));
  std::vector<double> tvals, nus;
  for (int b = 0; b < B; ++b) {
    double D[5], T[5];
    int ud = 0, ut = 0;
    bin_sums(cmp.data_stats, b, D, ud);
    bin_sums(cmp.twin_stats, b, T, ut);
    MapBin& mb = mp.bins[static_cast<std::size_t>(b)];
    const int i = b / setup.nv, jv = b % setup.nv;
    mb.x = setup.x_lo + (i + 0.5) * (setup.x_hi - setup.x_lo) / setup.nx;
    mb.v = setup.v_lo + (jv + 0.5) * (setup.v_hi - setup.v_lo) / setup.nv;
    const BinMoments md = bin_moments(D), mt = bin_moments(T);
    mb.n_data = md.n;
    mb.n_twin = mt.n / R;
    mb.mean_data = md.m;
    mb.mean_twin = mt.m;
    mb.var_data = md.var;
    mb.var_twin = mt.var;
    mb.kurt_data = md.kurt;
    mb.kurt_twin = mt.kurt;
    const double n_eff = effective_units(cmp, b);
    if (md.n < opt.min_bin_count || mt.n / R < opt.min_bin_count || ud < 2 || ut < 2 || U < 3 || n_eff < 4.0)
      continue;
    const std::array<double, 3> z = bin_z(cmp, b, D, T, md, mt);
    mb.z_mean = z[0];
    mb.z_var = z[1];
    mb.z_kurt = z[2];
    mb.used = true;
    tvals.push_back(z[0]);
    tvals.push_back(z[1]);
    nus.push_back(std::min(U - 1.0, n_eff - 1.0));
    nus.push_back(std::min(U - 1.0, n_eff - 1.0));
  }
  Component c{"one_step",
              "whitened one-step residual mean and log-variance per (x, v) bin, data vs twins",
              combine_t(tvals, nus)};
  if (!c.test.available) c.test.note = "no bin has " + fmt(opt.min_bin_count) + " rows on both sides";
  mp.worst = worst_bins(mp);
  mp.v_profile_mean = z2_profile(mp, true, true);
  mp.v_profile_var = z2_profile(mp, true, false);
  mp.x_profile_mean = z2_profile(mp, false, true);
  mp.x_profile_var = z2_profile(mp, false, false);
  return c;
}

}  // namespace vehs::diagnose::detail

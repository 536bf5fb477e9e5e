#include "vehs/identify/binned.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vehs/core/error.hpp"

namespace vehs::identify {

namespace {

/// Rows of a record are grouped in blocks of kBlock strides; block b goes to group b mod kGroups.
constexpr int kGroups = 20;
constexpr std::size_t kBlock = 200;

struct Sums {
  std::vector<double> n, s, s2;
  std::vector<double> gn, gs;  ///< per (bin, group): rows and sum
  explicit Sums(int bins) : n(bins, 0.0), s(bins, 0.0), s2(bins, 0.0), gn(bins * kGroups, 0.0), gs(gn) {}
  void add(int b, double v, int group = 0) {
    n[b] += 1.0, s[b] += v, s2[b] += v * v;
    gn[b * kGroups + group] += 1.0, gs[b * kGroups + group] += v;
  }
  /// Standard error of the mean of bin b: from the groups' spread (a ratio estimator), or as if
  /// the rows were independent when fewer than 5 groups hold rows.
  double se(int b) const {
    const double m = s[b] / n[b];
    double var = 0.0;
    int used = 0;
    for (int g = 0; g < kGroups; ++g) {
      const double ng = gn[b * kGroups + g];
      if (ng == 0) continue;
      ++used;
      const double d = ng / n[b] * (gs[b * kGroups + g] / ng - m);
      var += d * d;
    }
    if (used >= 5) return std::sqrt(var * used / (used - 1.0));
    return std::sqrt(std::max(0.0, s2[b] / n[b] - m * m) / (n[b] - 1.0));
  }
};

struct Range {
  double lo = 0.0, hi = 0.0;
  int bin(double v, int bins) const {
    const int b = static_cast<int>(std::floor((v - lo) / (hi - lo) * bins));
    return std::clamp(b, 0, bins - 1);
  }
};

/// The 0.5 % and 99.5 % quantiles of a sample of the values.
Range quantile_range(std::vector<double> v) {
  if (v.empty()) return {-1.0, 1.0};
  const auto q = [&](double p) {
    auto it = v.begin() + static_cast<std::ptrdiff_t>(p * static_cast<double>(v.size() - 1));
    std::nth_element(v.begin(), it, v.end());
    return *it;
  };
  Range r{q(0.005), q(0.995)};
  if (!(r.hi > r.lo)) r.hi = r.lo + 1.0;
  return r;
}

BinnedCurve finish(const Sums& s, const Range& r, int bins) {
  BinnedCurve c;
  for (int b = 0; b < bins; ++b) {
    c.at.push_back(r.lo + (b + 0.5) * (r.hi - r.lo) / bins);
    c.rows.push_back(s.n[b]);
    if (s.n[b] < 30) {
      c.mean.push_back(std::numeric_limits<double>::quiet_NaN());
      c.se.push_back(std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    c.mean.push_back(s.s[b] / s.n[b]);
    c.se.push_back(s.se(b));
  }
  return c;
}

/// Takes the sensor noise's part out of the diffusion bins. When it is more than the allowed
/// share of the raw diffusion pooled over the bins, every bin is dropped (deciding bin by bin
/// would keep exactly the bins whose noise fluctuated up).
void remove_noise(BinnedEstimates& out, const Sums& noise, const BinnedOptions& o) {
  out.noise_sd = o.noise_sd;
  if (o.noise_sd == 0.0) return;
  auto& c = out.diffusion;
  double raw = 0.0, part = 0.0;
  for (std::size_t b = 0; b < c.mean.size(); ++b)
    if (std::isfinite(c.mean[b]) && noise.n[b] > 0) raw += c.mean[b] * noise.n[b], part += noise.s[b];
  out.noise_share = raw > 0 ? part / raw : 0.0;
  const bool drop = out.noise_share > o.max_noise_share;
  for (std::size_t b = 0; b < c.mean.size(); ++b) {
    if (!std::isfinite(c.mean[b]) || noise.n[b] == 0) continue;
    if (drop) {
      c.mean[b] = c.se[b] = std::numeric_limits<double>::quiet_NaN();
      ++out.diffusion_bins_dropped;
      continue;
    }
    const double p = noise.s[b] / noise.n[b];
    c.mean[b] -= p;
    c.se[b] = std::hypot(c.se[b], 2 * p * o.noise_sd_se / o.noise_sd);
  }
}

/// White sensor noise of unit variance in c·h·(â − b2)², linearised in the noise: the weights of
/// x[i+k], x[i], x[i−k] in the residual, squared and summed.
double unit_noise_part(const TermList& drift, double x, double v, double u, double h, double c) {
  const double dx = 1e-6 * std::max(1.0, std::abs(x)), dv = 1e-6 * std::max(1.0, std::abs(v));
  const double gx = (evaluate(drift, x + dx, v, u) - evaluate(drift, x - dx, v, u)) / (2 * dx);
  const double gv = (evaluate(drift, x, v + dv, u) - evaluate(drift, x, v - dv, u)) / (2 * dv);
  const double a = 1 / (h * h), b = gv / (2 * h);
  return c * h * ((a - b) * (a - b) + (2 * a + gx) * (2 * a + gx) + (a + b) * (a + b));
}

}  // namespace

BinnedEstimates binned_estimates(const Dataset& data, const Model& model, const BinnedOptions& options) {
  const int bins = options.bins;
  require(bins >= 2, "binned_estimates: bins must be >= 2");
  require(options.noise_sd >= 0.0 && options.noise_sd_se >= 0.0, "binned_estimates: noise sd and its se must be >= 0");
  const int k = model.fit && model.fit->stride > 0 ? model.fit->stride : 1;
  const bool central = !model.fit || uses_central_kinematics(model.fit->estimator) || model.fit->estimator == Estimator::Auto;
  TermList x_only, y_part, u_part;
  for (const auto& tc : model.drift)
    (tc.term.depends_on_u() ? u_part : tc.term.depends_on_y() ? y_part : x_only).push_back(tc);
  const double c = central ? 1.5 : 1.0, s2 = options.noise_sd * options.noise_sd;
  // pass 1: ranges from every 16th row
  std::vector<double> xs, vs;
  for (const auto& r : data.records) {
    const double* x = data.x_of(r);
    const double h = k * r.dt;
    for (std::size_t i = static_cast<std::size_t>(k); i + static_cast<std::size_t>(k) < r.size; i += 16) {
      xs.push_back(x[i]);
      vs.push_back((x[i + k] - x[i - k]) / (2 * h));
    }
  }
  const Range rx = quantile_range(xs), rv = quantile_range(vs);
  // qv: rows and a22(x, v̂) per v̂ bin, with one bin of the same width beyond each end (the Itô
  // correction needs the density at the outer edges too)
  Sums dx(bins), dv(bins), dd(bins), qv(bins + 2), noise(bins);
  const double wv = (rv.hi - rv.lo) / bins;
  for (const auto& r : data.records) {
    const double* x = data.x_of(r);
    const double* u = data.u_of(r);
    const double h = k * r.dt;
    for (std::size_t i = static_cast<std::size_t>(k); i + static_cast<std::size_t>(k) < r.size; ++i) {
      const int group = static_cast<int>((r.offset + i) / (kBlock * static_cast<std::size_t>(k)) % kGroups);
      const double v = (x[i + k] - x[i - k]) / (2 * h);
      const double a = (x[i + k] - 2 * x[i] + x[i - k]) / (h * h);
      const double uu = u ? u[i] : 0.0;
      const double fx = evaluate(x_only, x[i], v, uu), fy = evaluate(y_part, x[i], v, uu);
      const double fu = evaluate(u_part, x[i], v, uu);
      if (x[i] >= rx.lo && x[i] <= rx.hi) {
        const int b = rx.bin(x[i], bins);
        dx.add(b, a - fy - fu, group);
        const double res = a - fx - fy - fu;
        dd.add(b, c * h * res * res, group);
        if (s2 > 0) noise.add(b, s2 * unit_noise_part(model.drift, x[i], v, uu, h, c));
      }
      if (v >= rv.lo && v <= rv.hi) dv.add(rv.bin(v, bins), a - fx - fu, group);
      if (v >= rv.lo - wv && v < rv.hi + wv)
        qv.add(std::clamp(static_cast<int>(std::floor((v - rv.lo) / wv)) + 1, 0, bins + 1), model.a22(x[i], v));
    }
  }
  BinnedEstimates out{finish(dx, rx, bins), finish(dv, rv, bins), finish(dd, rx, bins)};
  remove_noise(out, noise, options);
  if (central) {
    // â's noise covaries with v̂'s (a22/2 per unit of the indicator's v-derivative, Stein's
    // lemma as in ULI): E[â | v̂ ∈ [lo, hi)] = E[b2 | bin] + ½ (a22·p)(lo) − ½ (a22·p)(hi), over P(bin)
    double total = 0.0;  // rows of the whole data behind the densities
    for (const auto& r : data.records) total += static_cast<double>(r.size > 2 * static_cast<std::size_t>(k) ? r.size - 2 * static_cast<std::size_t>(k) : 0);
    // (bin b of dv is bin b + 1 of qv)
    auto density = [&](int b) { return qv.n[b + 1] / (total * wv); };
    auto a22 = [&](int b) { return qv.n[b + 1] == 0 ? 0.0 : qv.s[b + 1] / qv.n[b + 1]; };
    auto edge = [&](int lo_bin) {  // (a22·p) at the edge between bins lo_bin and lo_bin + 1
      return 0.5 * (a22(lo_bin) * density(lo_bin) + a22(lo_bin + 1) * density(lo_bin + 1));
    };
    for (int b = 0; b < bins; ++b)
      if (dv.n[b] > 0 && total > 0)
        out.drift_v.mean[static_cast<std::size_t>(b)] -= 0.5 * (edge(b - 1) - edge(b)) / (dv.n[b] / total);
  }
  return out;
}

}  // namespace vehs::identify

#include "vehs/identify/binned.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vehs/core/error.hpp"

namespace vehs::identify {

namespace {

struct Sums {
  std::vector<double> n, s, s2;
  explicit Sums(int bins) : n(bins, 0.0), s(bins, 0.0), s2(bins, 0.0) {}
  void add(int b, double v) {
    n[b] += 1.0, s[b] += v, s2[b] += v * v;
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
    const double m = s.s[b] / s.n[b];
    const double var = std::max(0.0, s.s2[b] / s.n[b] - m * m);
    c.mean.push_back(m);
    c.se.push_back(std::sqrt(var / (s.n[b] - 1.0)));
  }
  return c;
}

}  // namespace

BinnedEstimates binned_estimates(const Dataset& data, const Model& model, int bins) {
  require(bins >= 2, "binned_estimates: bins must be >= 2");
  const int k = model.fit && model.fit->stride > 0 ? model.fit->stride : 1;
  const bool central = !model.fit || uses_central_kinematics(model.fit->estimator) || model.fit->estimator == Estimator::Auto;
  TermList x_only, y_part;
  for (const auto& tc : model.drift) (tc.term.depends_on_y() || tc.term.depends_on_u() ? y_part : x_only).push_back(tc);
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
  Sums dx(bins), dv(bins), dd(bins), qv(bins + 2);
  const double wv = (rv.hi - rv.lo) / bins;
  for (const auto& r : data.records) {
    const double* x = data.x_of(r);
    const double* u = data.u_of(r);
    const double h = k * r.dt;
    for (std::size_t i = static_cast<std::size_t>(k); i + static_cast<std::size_t>(k) < r.size; ++i) {
      const double v = (x[i + k] - x[i - k]) / (2 * h);
      const double a = (x[i + k] - 2 * x[i] + x[i - k]) / (h * h);
      const double uu = u ? u[i] : 0.0;
      const double fx = evaluate(x_only, x[i], v, uu), fy = evaluate(y_part, x[i], v, uu);
      if (x[i] >= rx.lo && x[i] <= rx.hi) {
        dx.add(rx.bin(x[i], bins), a - fy);
        const double res = a - fx - fy;
        dd.add(rx.bin(x[i], bins), (central ? 1.5 : 1.0) * h * res * res);
      }
      if (v >= rv.lo && v <= rv.hi) dv.add(rv.bin(v, bins), a - fx);
      if (v >= rv.lo - wv && v < rv.hi + wv)
        qv.add(std::clamp(static_cast<int>(std::floor((v - rv.lo) / wv)) + 1, 0, bins + 1), model.a22(x[i], v));
    }
  }
  BinnedEstimates out{finish(dx, rx, bins), finish(dv, rv, bins), finish(dd, rx, bins)};
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

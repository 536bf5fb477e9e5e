#include "profile_search.hpp"

#include <algorithm>
#include <cmath>

#include "vehs/core/error.hpp"
#include "vehs/core/statistics.hpp"

namespace vehs::identify::detail {

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = kProfileInf;

/// Golden-section minimisation of f on [a, b] (in the transformed variable).
template <class F>
double golden(F f, double a, double b, int iters) {
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = f(c), fd = f(d);
  for (int i = 0; i < iters; ++i) {
    if (fc < fd) {
      b = d, d = c, fd = fc;
      c = b - g * (b - a);
      fc = f(c);
    } else {
      a = c, c = d, fc = fd;
      d = a + g * (b - a);
      fd = f(d);
    }
  }
  return fc < fd ? c : d;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const std::size_t i = std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<long>(i), v.end());
  return v[i];
}

/// Residuals of the baseline drift (no dynamic columns) along record r, at the row centres.
std::vector<double> baseline_residuals(const Problem& P, std::size_t r) {
  const Record& rec = P.data.records[r];
  std::vector<double> res;
  Problem::Rows rw;
  std::vector<double> scratch(P.phi.scratch_size());
  MatrixXd Z(kBlockRows, P.K());
  for (const auto& sp : spans_of(P, r))
    for (std::size_t i = sp.begin; i < sp.end; i += kBlockRows) {
      P.load(rec, i, sp.end, rw);
      P.phi.values(rw.b, Z.data(), kBlockRows, scratch.data());
      const VectorXd F = Z.topRows(rw.m) * P.c_base;
      for (int c = 0; c < rw.m; ++c) res.push_back(rw.b.a[c] - F[c]);
    }
  return res;
}

/// Candidate frequencies (rad/time) of the largest lines of the residual spectrum.
std::vector<double> spectral_lines(const Problem& P, int how_many, ComponentSearch& info) {
  std::size_t nmin = std::numeric_limits<std::size_t>::max();
  for (std::size_t r = 0; r < P.data.records.size(); ++r) {
    const std::size_t n = P.data.records[r].size;
    if (n > P.lead + P.trail) nmin = std::min(nmin, n - P.lead - P.trail);
  }
  std::size_t seg = 256;
  while (seg * 2 <= nmin && seg < (1u << 20)) seg *= 2;
  Spectrum total;
  for (std::size_t r = 0; r < P.data.records.size(); ++r) {
    const auto res = baseline_residuals(P, r);
    if (res.size() < seg) continue;
    accumulate_spectrum(total, welch_spectrum(res.data(), res.size(), P.dt, seg));
  }
  std::vector<double> out;
  const auto& f = total.frequency;
  const auto& S = total.density;
  if (f.size() < 16) return out;
  const double fmax = 0.25 / P.h;
  std::vector<std::pair<double, std::size_t>> peaks;
  const std::size_t W = 16;
  for (std::size_t i = 2; i + 1 < f.size(); ++i) {
    if (f[i] > fmax) break;
    if (!(S[i] >= S[i - 1] && S[i] >= S[i + 1])) continue;
    std::vector<double> nb;
    for (std::size_t j = (i > W ? i - W : 0); j < std::min(f.size(), i + W + 1); ++j)
      if (j + 3 < i || j > i + 3) nb.push_back(S[j]);
    const double med = quantile(nb, 0.5);
    if (med > 0) peaks.emplace_back(S[i] / med, i);
  }
  std::sort(peaks.begin(), peaks.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  info.spectral_lines.clear();
  for (int j = 0; j < how_many && j < static_cast<int>(peaks.size()); ++j) {
    out.push_back(2.0 * kPi * f[peaks[static_cast<std::size_t>(j)].second]);
    info.spectral_lines.push_back({f[peaks[static_cast<std::size_t>(j)].second], peaks[static_cast<std::size_t>(j)].first});
  }
  info.spectrum_segment = seg;
  return out;
}

/// Time span over which a harmonic force must stay coherent.
double time_span(const Dataset& d) {
  double lo = kInf, hi = -kInf;
  for (const auto& r : d.records) {
    lo = std::min(lo, r.t0);
    hi = std::max(hi, r.t0 + static_cast<double>(r.size) * r.dt);
  }
  return hi - lo;
}

double longest_record(const Dataset& d) {
  double T = 0.0;
  for (const auto& r : d.records) T = std::max(T, static_cast<double>(r.size) * r.dt);
  return T;
}

/// Joint Newton steps on the profile contrast over all free entries (finite-difference gradient
/// and Hessian, in log λ for the time constant): coordinate-wise search converges slowly when
/// entries are coupled (both gaps share k_stop).
int newton_polish(Problem& P, const std::vector<std::pair<int, int>>& free_th) {
  const int n = static_cast<int>(free_th.size());
  auto is_log = [&](int j) {
    return P.comps[static_cast<std::size_t>(free_th[static_cast<std::size_t>(j)].first)].id ==
           EffectId::ElectromechanicalCoupling;
  };
  auto get = [&](int j) {
    const auto [ci, sl] = free_th[static_cast<std::size_t>(j)];
    const double v = P.comps[static_cast<std::size_t>(ci)].theta[static_cast<std::size_t>(sl)];
    return is_log(j) ? std::log(v) : v;
  };
  auto eval = [&](const VectorXd& z) {
    auto th = P.thetas();
    for (int j = 0; j < n; ++j) {
      const auto [ci, sl] = free_th[static_cast<std::size_t>(j)];
      const Component& c = P.comps[static_cast<std::size_t>(ci)];
      const double v = is_log(j) ? std::exp(z[j]) : z[j];
      if (!c.theta_lo.empty() && (v < c.theta_lo[static_cast<std::size_t>(sl)] || v > c.theta_hi[static_cast<std::size_t>(sl)]))
        return kInf;
      th[static_cast<std::size_t>(ci)][static_cast<std::size_t>(sl)] = v;
    }
    return contrast_at(P, th);
  };
  VectorXd z(n), d(n);
  for (int j = 0; j < n; ++j) {
    z[j] = get(j);
    const auto id = P.comps[static_cast<std::size_t>(free_th[static_cast<std::size_t>(j)].first)].id;
    d[j] = is_log(j) ? 0.02 : id == EffectId::HarmonicForcing ? 2.0 * kPi / (8.0 * time_span(P.data))
                                                             : 2e-3 * std::max(std::abs(z[j]), 1e-6);
  }
  double f0 = eval(z);
  int it = 0;
  for (; it < 8; ++it) {
    VectorXd gr(n);
    MatrixXd H(n, n);
    std::vector<double> fp(static_cast<std::size_t>(n)), fm(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      VectorXd a = z, b = z;
      a[i] += d[i];
      b[i] -= d[i];
      fp[static_cast<std::size_t>(i)] = eval(a);
      fm[static_cast<std::size_t>(i)] = eval(b);
      gr[i] = (fp[static_cast<std::size_t>(i)] - fm[static_cast<std::size_t>(i)]) / (2 * d[i]);
      H(i, i) = (fp[static_cast<std::size_t>(i)] - 2 * f0 + fm[static_cast<std::size_t>(i)]) / (d[i] * d[i]);
    }
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) {
        VectorXd pp = z, mm = z;
        pp[i] += d[i], pp[j] += d[j];
        mm[i] -= d[i], mm[j] -= d[j];
        // f(+i+j) + f(−i−j) = 2f0 + d_i²H_ii + d_j²H_jj + 2 d_i d_j H_ij
        H(i, j) = H(j, i) = (eval(pp) + eval(mm) - 2 * f0 - d[i] * d[i] * H(i, i) - d[j] * d[j] * H(j, j)) /
                            (2 * d[i] * d[j]);
      }
    const Eigen::SelfAdjointEigenSolver<MatrixXd> es(H);
    if (es.eigenvalues().minCoeff() <= 0) break;  // not locally convex: keep the coordinate result
    VectorXd step = -H.ldlt().solve(gr);
    bool moved = false;
    for (double lam = 1.0; lam > 0.05; lam *= 0.5) {
      const VectorXd zn = z + lam * step;
      const double fn = eval(zn);
      if (fn < f0) {
        z = zn, f0 = fn, moved = true;
        break;
      }
    }
    if (!moved) break;
    bool small = true;
    for (int j = 0; j < n; ++j) small = small && std::abs(step[j]) < 0.05 * d[j];
    if (small) break;
  }
  for (int j = 0; j < n; ++j) {
    const auto [ci, sl] = free_th[static_cast<std::size_t>(j)];
    P.comps[static_cast<std::size_t>(ci)].theta[static_cast<std::size_t>(sl)] = is_log(j) ? std::exp(z[j]) : z[j];
  }
  return it;
}

/// |x| of each side (positive x, negative x), subsampled and sorted: the gaps of impact stops are
/// searched between the median of a side and its largest excursion — a stop acts at the
/// extremes, and a gap near 0 would turn the stop into a stiffness term (collinear with x).
struct SideQuantiles {
  std::vector<double> pos, neg;
  explicit SideQuantiles(const Dataset& data) {
    for (const auto& r : data.records) {
      const double* x = data.x_of(r);
      for (std::size_t i = 0; i < r.size; i += 3) (x[i] > 0 ? pos : neg).push_back(std::abs(x[i]));
    }
    std::sort(pos.begin(), pos.end());
    std::sort(neg.begin(), neg.end());
  }
  static double at(const std::vector<double>& v, double q) {
    if (v.empty()) return 1e-12;
    return std::max(v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())))], 1e-12);
  }
};

/// Search brackets of every nonlinear parameter (gaps: between the median and the 0.9999 quantile of their side).
void set_brackets(Problem& P, const SideQuantiles& sides) {
  for (auto& c : P.comps) {
    c.theta_lo.assign(c.theta.size(), 1e-12);
    c.theta_hi.assign(c.theta.size(), kInf);
    if (c.id == EffectId::ImpactStop) {
      c.theta_lo = {SideQuantiles::at(sides.pos, 0.5), SideQuantiles::at(sides.neg, 0.5)};
      c.theta_hi = {SideQuantiles::at(sides.pos, 0.9999), SideQuantiles::at(sides.neg, 0.9999)};
    }
  }
}

/// Impact stop i: a joint grid over matching quantiles of both sides.
void start_stop(const Problem& Q, std::size_t i, const SideQuantiles& sides, Component& c, ComponentSearch& ci) {
  static const std::vector<double> qs = {0.5, 0.6, 0.7, 0.8, 0.85, 0.9, 0.93, 0.95, 0.97, 0.98, 0.99, 0.995, 0.998};
  double best = kInf;
  std::vector<double> gp, gn;
  for (double q : qs) {
    gp.push_back(SideQuantiles::at(sides.pos, q));
    gn.push_back(SideQuantiles::at(sides.neg, q));
  }
  std::size_t jb = 0;
  for (std::size_t j = 0; j < qs.size(); ++j) {
    auto th = Q.thetas();
    if (c.theta_free[0]) th[i][0] = gp[j];
    if (c.theta_free[1]) th[i][1] = gn[j];
    const double v = contrast_at(Q, th);
    if (v < best) best = v, jb = j;
  }
  if (c.theta_free[0]) c.theta[0] = gp[jb];
  if (c.theta_free[1]) c.theta[1] = gn[jb];
  ci.grid_quantile = qs[jb];
}

/// Electromechanical coupling i: λ on a log grid from 1/(longest record) to 0.2/h.
void start_electro(const Problem& P, const Problem& Q, std::size_t i, Component& c, ComponentSearch& ci) {
  const double lo = 1.0 / longest_record(P.data), hi = 0.2 / P.h;
  double best = kInf;
  for (int j = 0; j < 24; ++j) {
    const double lam = lo * std::pow(hi / lo, j / 23.0);
    auto th = Q.thetas();
    th[i][0] = lam;
    const double v = contrast_at(Q, th);
    if (v < best) best = v, c.theta[0] = lam;
  }
  ci.lambda_grid = std::array<double, 3>{lo, hi, 24.0};
}

/// Harmonic forcing i: ω scanned around the largest lines of the residual spectrum.
void start_harmonic(const Problem& P, const Problem& Q, std::size_t i, Component& c, ComponentSearch& ci) {
  const auto lines = spectral_lines(P, 3, ci);
  require(!lines.empty(), "harmonic_forcing: the residual spectrum has no line to start from");
  const double T = time_span(P.data);
  double best = kInf;
  for (double w0 : lines) {
    // scan ±1.5 Welch bins at a quarter of the coherent resolution 2π/T
    const double seg_res = 2.0 * kPi / (static_cast<double>(ci.spectrum_segment) * P.dt);
    const double step = std::max(2.0 * kPi / (4.0 * T), 3.0 * seg_res / 400.0);
    for (double w = w0 - 1.5 * seg_res; w <= w0 + 1.5 * seg_res; w += step) {
      if (w <= 0) continue;
      auto th = Q.thetas();
      th[i][0] = w;
      const double v = contrast_at(Q, th);
      if (v < best) best = v, c.theta[0] = w;
    }
  }
  ci.scan_step = std::max(2.0 * kPi / (4.0 * T), 0.0);
}

/// Refines free entry (ci, s): a scan of its bracket (the profile is rough on the scale of the
/// sample spacing for gaps), then golden section around the best scan point.
void refine_entry(Problem& P, int ci, int s, bool wide) {
  Component& c = P.comps[static_cast<std::size_t>(ci)];
  const double v0 = c.theta[static_cast<std::size_t>(s)];
  double a, b;
  int scan = 7;
  bool logs = false;
  if (c.id == EffectId::ImpactStop) {
    const double span = std::max((wide ? 0.15 : 0.03) * v0, 1e-9);
    a = std::max(v0 - span, 1e-12), b = v0 + span;
    scan = wide ? 21 : 9;
  } else if (c.id == EffectId::ElectromechanicalCoupling) {
    logs = true;
    const double lo = 1.0 / longest_record(P.data), hi = 0.2 / P.h;
    const double r = std::pow(hi / lo, 1.0 / 23.0);
    a = std::log(v0 / r), b = std::log(v0 * r);
    scan = 9;
  } else {
    const double step = 2.0 * kPi / (4.0 * time_span(P.data));
    a = v0 - 1.5 * step, b = v0 + 1.5 * step;
  }
  const double lo = c.theta_lo[static_cast<std::size_t>(s)], hi = c.theta_hi[static_cast<std::size_t>(s)];
  auto f = [&](double z) {
    const double v = logs ? std::exp(z) : z;
    if (v < lo || v > hi) return kInf;
    auto th = P.thetas();
    th[static_cast<std::size_t>(ci)][static_cast<std::size_t>(s)] = v;
    return contrast_at(P, th);
  };
  const double z0 = logs ? std::log(v0) : v0;
  double zbest = z0, fbest = f(z0);
  const double dz = (b - a) / (scan - 1);
  for (int j = 0; j < scan; ++j) {
    const double z = a + j * dz;
    const double v = f(z);
    if (v < fbest) fbest = v, zbest = z;
  }
  const double z = golden(f, zbest - dz, zbest + dz, 24);
  if (f(z) < fbest) zbest = z;
  c.theta[static_cast<std::size_t>(s)] = logs ? std::exp(zbest) : zbest;
}

}  // namespace

void search_theta(Problem& P, ProfileFitReport& info, bool warm) {
  info.search.clear();
  info.newton_iterations = -1;
  const auto free_th = P.free_theta();
  if (free_th.empty()) return;
  const SideQuantiles sides(P.data);
  set_brackets(P, sides);
  for (std::size_t i = 0; i < (warm ? 0 : P.comps.size()); ++i) {
    Component& c = P.comps[i];
    ComponentSearch ci;
    ci.effect = c.id;
    // the grid of component i runs with the components initialised so far (later ones still
    // have placeholder parameters, e.g. ω = 0 makes the sin column vanish)
    Problem Q = P;
    Q.comps.assign(P.comps.begin(), P.comps.begin() + static_cast<long>(i) + 1);
    if (c.id == EffectId::ImpactStop)
      start_stop(Q, i, sides, c, ci);
    else if (c.id == EffectId::ElectromechanicalCoupling && c.theta_free[0])
      start_electro(P, Q, i, c, ci);
    else if (c.id == EffectId::HarmonicForcing && c.theta_free[0])
      start_harmonic(P, Q, i, c, ci);
    info.search.push_back(std::move(ci));
  }
  // two refinement cycles when there are several entries (the first over wider brackets)
  const int cycles = free_th.size() > 1 && !warm ? 2 : 1;
  for (int cy = 0; cy < cycles; ++cy)
    for (const auto& [ci, s] : free_th) refine_entry(P, ci, s, cy == 0 && !warm);
  if (free_th.size() > 1) info.newton_iterations = newton_polish(P, free_th);
}

}  // namespace vehs::identify::detail

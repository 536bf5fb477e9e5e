// Moments, marginals, identities and wells of a stationary density; the automatic domain and
// the boundary-mass check.
#include <algorithm>
#include <cmath>
#include <limits>

#include "vehs/conventions.hpp"
#include "vehs/core/detail/format.hpp"
#include "vehs/core/error.hpp"
#include "vehs/effects/from_model.hpp"
#include "vehs/fpk/solve.hpp"

namespace vehs::fpk {

/// Negative density mass beyond which a solution is rejected as unresolved.
constexpr double kMaxUndershoot = 1e-3;

namespace {
std::string num(double v) { return vehs::detail::format_number(v, 4); }
}  // namespace

std::vector<Well> find_wells(const FpkModel& model, double lo, double hi) {
  const int n = 4000;
  const double h = (hi - lo) / n;
  auto f = [&](double x) { return model.restoring_force(x); };
  auto refine = [&](double a, double b) {
    double fa = f(a);
    for (int it = 0; it < 60; ++it) {
      const double m = 0.5 * (a + b);
      const double fm = f(m);
      if ((fm > 0) == (fa > 0)) {
        a = m;
        fa = fm;
      } else {
        b = m;
      }
    }
    return 0.5 * (a + b);
  };
  // Sign changes between consecutive grid points where the force is non-zero: a grid point that
  // lands exactly on a root (x = 0 of an odd force, depending on how lo + k·h rounds) is
  // bracketed by its non-zero neighbours and counted once.
  std::vector<double> minima, maxima;
  double prev_x = lo, prev = f(lo);
  for (int k = 1; k <= n; ++k) {
    const double x = lo + k * h;
    const double cur = f(x);
    if (cur == 0.0) continue;
    if (prev < 0.0 && cur > 0.0) minima.push_back(refine(prev_x, x));
    if (prev > 0.0 && cur < 0.0) maxima.push_back(refine(prev_x, x));
    prev = cur;
    prev_x = x;
  }
  std::vector<Well> wells;
  if (minima.empty()) {
    Well w;
    w.x_min = model.potential(lo) <= model.potential(hi) ? lo : hi;
    w.potential = model.potential(w.x_min);
    w.lo = lo;
    w.hi = hi;
    wells.push_back(w);
    return wells;
  }
  for (double xm : minima) {
    Well w;
    w.x_min = xm;
    w.potential = model.potential(xm);
    w.lo = lo;
    w.hi = hi;
    for (double mx : maxima) {
      if (mx < xm) w.lo = std::max(w.lo, mx);
      if (mx > xm) w.hi = std::min(w.hi, mx);
    }
    wells.push_back(w);
  }
  return wells;
}

void analyse_density(const FpkModel& model, StationaryResult& r) {
  const Grid& g = r.grid;
  const int nx = g.x.n, ny = g.y.n;
  const double hx = g.x.h(), hy = g.y.h(), area = g.cell_area();
  r.marginal_x.assign(static_cast<std::size_t>(nx), 0.0);
  r.marginal_y.assign(static_cast<std::size_t>(ny), 0.0);
  Moments m;
  double bx = 0.0, by = 0.0, ring = 0.0, undershoot = 0.0;
  for (int i = 0; i < nx; ++i) {
    const double x = g.x.center(i);
    for (int j = 0; j < ny; ++j) {
      const double y = g.y.center(j);
      const double w = r.density[g.index(i, j)] * area;
      r.marginal_x[static_cast<std::size_t>(i)] += w / hx;
      r.marginal_y[static_cast<std::size_t>(j)] += w / hy;
      const double b = model.b2(x, y);
      m.mass += w;
      m.ex += w * x;
      m.ey += w * y;
      m.exx += w * x * x;
      m.eyy += w * y * y;
      m.exy += w * x * y;
      m.x_b2 += w * x * b;
      m.y_b2 += w * y * b;
      m.a22 += w * model.a22(x, y);
      const bool edge_x = i == 0 || i == nx - 1, edge_y = j == 0 || j == ny - 1;
      if (edge_x) bx += w;
      if (edge_y) by += w;
      if (edge_x || edge_y) (w > 0.0 ? ring : undershoot) += w;
    }
  }
  r.moments = m;
  r.boundary_mass = ring;
  r.boundary_undershoot = undershoot;
  r.boundary_mass_x = bx;
  r.boundary_mass_y = by;
  Identities& id = r.identities;
  const double sxy = std::sqrt(std::max(m.exx * m.eyy, 0.0));
  id.xy = sxy > 0 ? m.exy / sxy : 0.0;
  id.virial = m.eyy > 0 ? (m.eyy + m.x_b2) / m.eyy : 0.0;
  id.energy = m.a22 > 0 ? (m.y_b2 + 0.5 * m.a22) / (0.5 * m.a22) : 0.0;
  // wells: mass of the x-marginal between neighbouring maxima (cells split proportionally)
  r.wells = find_wells(model, g.x.min, g.x.max);
  for (auto& w : r.wells) {
    w.mass = 0.0;
    for (int i = 0; i < nx; ++i) {
      const double a = g.x.face(i), b = g.x.face(i + 1);
      const double overlap = std::max(0.0, std::min(b, w.hi) - std::max(a, w.lo));
      w.mass += r.marginal_x[static_cast<std::size_t>(i)] * overlap;
    }
  }
}

// ---- automatic domain -------------------------------------------------------------------------

namespace {

/// Fujiwara's bound of the roots of the x-only restoring force (polynomial part, and the same
/// with each stop's linear force added), so that beyond it U' keeps its sign. Cauchy's bound,
/// 1 + max |a_i/a_n|, scales with the coefficients' ratio rather than its root: a Duffing in ADC
/// counts (3948 x + 0.0015 x³, roots ±1622i) got 2.6e6, beyond the scan's reach, and no FPK
/// reference ("no stationary density found within |x| < 1e6"); Fujiwara's is 3244.
double root_bound(const Model& m) {
  std::vector<double> a(1, 0.0);
  for (const auto& tc : m.drift)
    if (tc.term.kind == TermKind::Monomial && tc.term.py == 0) {
      if (static_cast<int>(a.size()) <= tc.term.px) a.resize(static_cast<std::size_t>(tc.term.px) + 1, 0.0);
      a[static_cast<std::size_t>(tc.term.px)] += -tc.coef;
    }
  auto cauchy = [](std::vector<double> c) {  // Fujiwara: 2 max_k |a_{n−k}/a_n|^{1/k}, the last term halved
    while (c.size() > 1 && c.back() == 0.0) c.pop_back();
    if (c.size() <= 1) return 0.0;
    const std::size_t n = c.size() - 1;
    double mx = 0.0;
    for (std::size_t k = 1; k <= n; ++k) {
      const double r = std::abs(c[n - k] / c[n]) / (k == n ? 2.0 : 1.0);
      mx = std::max(mx, std::pow(r, 1.0 / static_cast<double>(k)));
    }
    return 2.0 * mx;
  };
  double bound = cauchy(a);
  if (const Effect* e = m.find_effect(EffectId::ImpactStop)) {
    // beyond a stop U' gains an affine part −force(x) = k·x ∓ k·gap (either sign, either gap)
    const auto stop = effects::from_effect<effects::ImpactStop>(*e);
    for (const auto& piece : stop.outer_pieces()) {
      auto b = a;
      if (b.size() < 2) b.resize(2, 0.0);
      b[1] -= piece.slope;
      b[0] -= std::abs(piece.offset);
      bound = std::max({bound, cauchy(b), std::abs(piece.offset / piece.slope)});
      b[0] += 2 * std::abs(piece.offset);
      bound = std::max(bound, cauchy(b));
    }
  }
  return bound;
}

}  // namespace

Grid automatic_domain(const FpkModel& model, int nx, int ny, const DomainOptions& o) {
  const double K = o.log_density_drop;
  require(K > 0.0, "log_density_drop must be > 0");
  const double bound = root_bound(model.model());
  auto integrand = [&](double x) {
    const double t = model.temperature(x);
    return model.restoring_force(x) / std::max(t, 1e-300);
  };
  // Φ on geometric grids from 0 outwards on each side.
  const double s0 = 1e-9, ratio = 1.02, s_limit = 1e6;
  auto scan = [&](double dir) {
    std::vector<std::pair<double, double>> pts;  // (x, Φ)
    double x_prev = 0.0, f_prev = integrand(0.0), phi = 0.0, phi_min = 0.0;
    pts.emplace_back(0.0, 0.0);
    for (double s = s0;; s *= ratio) {
      require(s < s_limit, model.where() +
                               ": no stationary density found within |x| < 1e6: the log-density "
                               "grows too slowly (the noise grows as fast as the potential; e.g. "
                               "for a linear oscillator E[X^2] = D/(beta*k1 - Q) needs Q < beta*k1)");
      const double x = dir * s;
      const double f = integrand(x);
      phi += 0.5 * (f + f_prev) * (x - x_prev);
      require(std::isfinite(phi), model.where() + ": the local log-density is not finite at x = " +
                                      num(x) + " (check the diffusion near this point)");
      x_prev = x;
      f_prev = f;
      phi_min = std::min(phi_min, phi);
      pts.emplace_back(x, phi);
      if (s > bound && phi - phi_min > K + 5.0 && dir * model.restoring_force(x) > 0.0) break;
    }
    return pts;
  };
  auto right = scan(1.0), left = scan(-1.0);
  std::vector<std::pair<double, double>> all(left.rbegin(), left.rend());
  all.insert(all.end(), right.begin() + 1, right.end());
  double phi_min = std::numeric_limits<double>::infinity();
  for (const auto& pt : all) phi_min = std::min(phi_min, pt.second);
  std::size_t first = all.size(), last = 0;
  for (std::size_t k = 0; k < all.size(); ++k)
    if (all[k].second - phi_min <= K) {
      first = std::min(first, k);
      last = std::max(last, k);
    }
  Grid g;
  g.x.min = all[first > 0 ? first - 1 : 0].first;
  g.x.max = all[std::min(last + 1, all.size() - 1)].first;
  g.x.n = nx;
  // y: largest velocity range that local equilibrium predicts above e^−K of the peak.
  const int m = 2000;
  const double h = (g.x.max - g.x.min) / m;
  std::vector<double> phi(m + 1, 0.0), temp(m + 1, 0.0);
  double f_prev = 0.0;
  for (int k = 0; k <= m; ++k) {
    const double x = g.x.min + k * h;
    temp[static_cast<std::size_t>(k)] = model.temperature(x);
    const double f = model.restoring_force(x) / std::max(temp[static_cast<std::size_t>(k)], 1e-300);
    if (k > 0) phi[static_cast<std::size_t>(k)] = phi[static_cast<std::size_t>(k) - 1] + 0.5 * (f + f_prev) * h;
    f_prev = f;
  }
  const double pm = *std::min_element(phi.begin(), phi.end());
  double y2 = 0.0;
  for (int k = 0; k <= m; ++k)
    y2 = std::max(y2, 2.0 * temp[static_cast<std::size_t>(k)] *
                          std::max(0.0, K - (phi[static_cast<std::size_t>(k)] - pm)));
  require(y2 > 0.0 && std::isfinite(y2),
          model.where() + ": cannot size the velocity range (no noise where the density sits?)");
  g.y.min = -std::sqrt(y2);
  g.y.max = std::sqrt(y2);
  g.y.n = ny;
  return g;
}

std::string DomainOptions::invalid_reason() const {
  if (!(log_density_drop > 0.0) || !std::isfinite(log_density_drop)) return "log_density_drop must be > 0";
  if (!(boundary_mass_tolerance > 0.0) || !std::isfinite(boundary_mass_tolerance))
    return "boundary_mass_tolerance must be > 0";
  if (max_cells < 0) return "max_cells must be >= 0";
  return "";
}

namespace {

/// Thrown inside solve_on when the grid does not resolve the model.
struct Unresolved {
  std::string why;
};

StationaryResult solve_on(const FpkModel& model, const GridRequest& request, Grid grid, const SolveOptions& options,
                          const DomainOptions& domain) {
  const double tol = domain.boundary_mass_tolerance;
  if (request.auto_x || request.auto_y) {
    const Grid a = automatic_domain(model, grid.x.n, grid.y.n, domain);
    if (request.auto_x) grid.x = a.x;
    if (request.auto_y) grid.y = a.y;
  }
  const int max_enlargements = 6;
  double previous = -1.0;
  for (int attempt = 0;; ++attempt) {
    StationaryResult res;
    try {
      res = solve_stationary(model, grid, options);
    } catch (const SolveBreakdown&) {
      throw Unresolved{"the solution has no positive mass on " + std::to_string(grid.x.n) + "x" +
                       std::to_string(grid.y.n) + " cells over x in [" + num(grid.x.min) + ", " + num(grid.x.max) +
                       "], y in [" + num(grid.y.min) + ", " + num(grid.y.max) + "] (too few cells, or a domain that misses the density)"};
    }
    res.auto_domain = request.auto_x || request.auto_y;
    res.domain_enlargements = attempt;
    if (!res.summary.converged)  // an unconverged iterate says nothing about the domain
      throw Error(model.where() + ": the " + res.summary.solver + " solver did not converge in " +
                  std::to_string(res.summary.iterations) +
                  " iterations on " + std::to_string(grid.x.n) + "x" + std::to_string(grid.y.n) +
                  " cells (raise max_iterations or use the direct solver)");
    const std::string cells = std::to_string(grid.x.n) + "x" + std::to_string(grid.y.n) + " cells";
    if (std::abs(res.boundary_signed_mass()) <= tol) {
      if (res.summary.negative_mass < -kMaxUndershoot)
        throw Unresolved{"the solution undershoots (negative density of total mass " +
                         num(res.summary.negative_mass) + " on " + cells + ")"};
      return res;
    }
    const double mx = std::abs(res.boundary_mass_x), my = std::abs(res.boundary_mass_y);
    const bool bad_x = mx > 0.5 * tol || !(my > 0.5 * tol);
    const bool bad_y = my > 0.5 * tol || !(mx > 0.5 * tol);
    std::string user_axes;
    for (int ax = 0; ax < 2; ++ax) {
      const bool bad = ax == 0 ? bad_x : bad_y;
      const bool automatic = ax == 0 ? request.auto_x : request.auto_y;
      if (bad && !automatic) {
        const Axis& a = ax == 0 ? grid.x : grid.y;
        user_axes += std::string(user_axes.empty() ? "" : "; ") + "grid." + (ax == 0 ? "x" : "y") +
                     " [" + num(a.min) + ", " + num(a.max) + "]: " + num(ax == 0 ? mx : my);
      }
    }
    if (!user_axes.empty())
      throw Error("too much probability mass in the boundary cells of the given domain (" + user_axes +
                  "; allowed in total: " + num(tol) +
                  "); enlarge the domain, omit the axis for an automatic range, or raise "
                  "boundary_mass_tolerance");
    // an enlarged domain with coarser cells that keeps as much mass on its boundary: the
    // boundary mass is discretisation error, not tails
    if (previous >= 0.0 && std::abs(res.boundary_signed_mass()) > 0.5 * previous)
      throw Unresolved{num(res.boundary_signed_mass()) + " of the mass stays on the boundary of " + cells +
                       " when the automatic domain is enlarged"};
    if (attempt >= max_enlargements && res.boundary_signed_mass() < 0.0)  // oscillations, not tails
      throw Unresolved{"negative density on the domain's edges (boundary mass " + num(res.boundary_signed_mass()) + " on " +
                       cells + ")"};
    if (attempt >= max_enlargements)
      throw Error(model.where() + ": " + num(res.boundary_signed_mass()) + " of the mass stays on the boundary after " +
                  std::to_string(max_enlargements) + " enlargements of the automatic domain (heavy tails?)");
    previous = std::abs(res.boundary_signed_mass());
    DomainOptions wider = domain;
    wider.log_density_drop = domain.log_density_drop + 8.0 * (attempt + 1);
    const Grid a = automatic_domain(model, grid.x.n, grid.y.n, wider);
    if (request.auto_x && bad_x) grid.x = a.x;
    if (request.auto_y && bad_y) grid.y = a.y;
  }
}

}  // namespace

StationaryResult solve_with_domain(const FpkModel& model, const GridRequest& request,
                                   const SolveOptions& options, const DomainOptions& domain) {
  if (auto why = domain.invalid_reason(); !why.empty()) throw Error(why);
  Grid grid = request.grid;
  for (int refinements = 0;; ++refinements) {
    try {
      StationaryResult res = solve_on(model, request, grid, options, domain);
      res.refinements = refinements;
      return res;
    } catch (const Unresolved& u) {
      const bool can_refine = (request.auto_x || request.auto_y) && 2 * std::max(grid.x.n, grid.y.n) <= domain.max_cells;
      if (!can_refine)
        throw Error(model.where() + ": the grid does not resolve the model: " + u.why + "; use at least " +
                    std::to_string(2 * grid.x.n) + "x" + std::to_string(2 * grid.y.n) + " cells" +
                    (domain.max_cells > 0 ? " (automatic refinement stops at " + std::to_string(domain.max_cells) +
                                                " cells per axis)"
                                          : ""));
      grid.x.n *= 2;
      grid.y.n *= 2;
    }
  }
}

}  // namespace vehs::fpk

// Timings of the stationary FPK solvers (one core) and the paper's SOR next to the direct solve.
//
//   bench_fpk            all cases (incl. 1000x1000, ~1 min)
//   bench_fpk --quick    skip 1000x1000
//
// Model: the paper's learned penta-stable harvester (Tables 2-3). Reference for accuracy: the
// direct flux solve on 800x800 cells of the automatic domain.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "vehs/core/parallel.hpp"
#include "vehs/core/model.hpp"
#include "vehs/fpk/stationary.hpp"

using namespace vehs;
using namespace vehs::fpk;

namespace {

Model learned() {
  return Model::paper(0.1010, {{1, 0.9976}, {3, -7.7182}, {5, 16.3409}, {7, -12.5293}, {9, 3.1068}}, 0.0194, 0.0116);
}

double wall(const std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// L1 distance of the x-marginals of two solutions (on their own grids; b is the finer reference,
/// interpolated linearly to a's cell centres).
double marginal_l1(const StationaryResult& a, const StationaryResult& ref) {
  double s = 0.0;
  for (int i = 0; i < a.grid.x.n; ++i) {
    const double x = a.grid.x.center(i);
    const double u = (x - ref.grid.x.min) / ref.grid.x.h() - 0.5;
    double pr = 0.0;
    if (u >= 0 && u <= ref.grid.x.n - 1) {
      const int k = std::min(static_cast<int>(u), ref.grid.x.n - 2);
      const double w = u - k;
      pr = (1 - w) * ref.marginal_x[static_cast<std::size_t>(k)] + w * ref.marginal_x[static_cast<std::size_t>(k) + 1];
    }
    s += std::abs(a.marginal_x[static_cast<std::size_t>(i)] - pr) * a.grid.x.h();
  }
  return s;
}

void row(const char* label, const StationaryResult& r, double seconds, const StationaryResult* ref) {
  std::printf("%-34s %5dx%-5d %8.3f s  E[X^2] %.6f  E[Y^2] %.6f", label, r.grid.x.n, r.grid.y.n, seconds,
              r.moments.exx, r.moments.eyy);
  if (ref)
    std::printf("  dE[Y^2] %+.1e  L1(p(x)) %.1e", r.moments.eyy / ref->moments.eyy - 1, marginal_l1(r, *ref));
  if (r.summary.factor_nonzeros)
    std::printf("  LU nnz %.3g (%.0f MB)", static_cast<double>(r.summary.factor_nonzeros), r.summary.factor_megabytes);
  if (r.summary.solver == "sor")
    std::printf("  %ld sweeps%s, residual %.1e", r.summary.iterations, r.summary.converged ? "" : " (not converged)",
                r.summary.residual);
  std::printf("\n");
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  set_threads(1);
  const FpkModel m(learned());
  std::printf("fpk bench: the paper's learned model, one thread (UMFPACK with the system's BLAS)\n");
  const Grid dom = automatic_domain(m, 100, 100);
  std::printf("automatic domain x [%.4f, %.4f], y [%.4f, %.4f]\n\n", dom.x.min, dom.x.max, dom.y.min, dom.y.max);

  auto solve = [&](int n, Scheme s, Ordering o, const Grid& base, int corrections = 2) {
    Grid g = base;
    g.x.n = g.y.n = n;
    SolveOptions opt;
    opt.scheme = s;
    opt.ordering = o;
    opt.correction_steps = corrections;
    const auto t0 = std::chrono::steady_clock::now();
    StationaryResult r = solve_stationary(m, g, opt);
    return std::make_pair(r, wall(t0));
  };
  const auto [ref, ref_t] = solve(800, Scheme::Flux, Ordering::Metis, dom);
  row("reference: direct flux", ref, ref_t, nullptr);
  std::printf("\n-- direct solves (assembly + analysis + factorisation + solve) --\n");
  for (int n : {400, 1000}) {
    if (n == 1000 && quick) continue;
    for (int variant = 0; variant < 3; ++variant)
      for (Ordering o : {Ordering::Amd, Ordering::Metis}) {
        if (n == 1000 && variant > 0) continue;
        const Scheme s = variant == 2 ? Scheme::Flux2 : Scheme::Flux;
        const int corrections = variant == 1 ? 0 : 2;
        const auto [r, t] = solve(n, s, o, dom, corrections);
        const std::string label = std::string(variant == 0 ? "flux (LU flux2 + 2 corr.)"
                                              : variant == 1 ? "flux (exact 7-point LU)"
                                                             : "flux2") +
                                  " " + enum_to_string(kOrderingNames, o);
        row(label.c_str(), r, t, &ref);
      }
  }

  std::printf("\n-- the paper's method: Eq. 35 central, SOR alpha 0.01, tol 1e-5, normalise every 10, "
              "50x50 on [-1.6, 1.6]^2 --\n");
  Grid paper;
  paper.x = {-1.6, 1.6, 50};
  paper.y = {-1.6, 1.6, 50};
  SolveOptions sor;
  sor.scheme = Scheme::Central;
  sor.solver = Solver::Sor;
  auto t0 = std::chrono::steady_clock::now();
  const StationaryResult rs = solve_stationary(m, paper, sor);
  row("paper SOR (central)", rs, wall(t0), &ref);
  std::printf("   boundary mass %.2e (the domain cuts the density)\n", rs.boundary_mass);
  SolveOptions same;
  same.scheme = Scheme::Central;
  t0 = std::chrono::steady_clock::now();
  const StationaryResult rd = solve_stationary(m, paper, same);
  row("direct, same central 50x50 system", rd, wall(t0), &ref);
  std::printf("   the same discrete system solved exactly: SOR's stopping rule leaves L1 %.1e between them\n",
              [&] {
                double s = 0.0;
                for (std::size_t k = 0; k < rs.density.size(); ++k) s += std::abs(rs.density[k] - rd.density[k]);
                return s * paper.cell_area();
              }());
  // the smallest direct flux solve on the automatic domain at least as accurate in E[Y^2]
  const double sor_err = std::abs(rs.moments.eyy / ref.moments.eyy - 1);
  for (int n : {40, 60, 80, 100, 120, 160, 200}) {
    const auto [r, t] = solve(n, Scheme::Flux, Ordering::Amd, dom);
    if (std::abs(r.moments.eyy / ref.moments.eyy - 1) <= sor_err && r.summary.negative_mass > -1e-3) {
      row("direct flux, equal or better E[Y^2]", r, t, &ref);
      break;
    }
  }
  return 0;
}

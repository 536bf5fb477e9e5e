// Parameter sweeps of the stationary FPK on one shared grid, in parallel.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "vehs/core/detail/memory.hpp"
#include "vehs/core/error.hpp"
#include "vehs/core/parallel.hpp"
#include "vehs/core/detail/progress_counter.hpp"
#include "vehs/core/parameters.hpp"
#include "vehs/fpk/sweep.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace vehs::fpk {

std::string SweepOptions::invalid_reason() const {
  if (auto why = solve.invalid_reason(); !why.empty()) return why;
  return domain.invalid_reason();
}

namespace {

/// Every point's model (product order, last axis fastest) with its parameter values.
std::vector<Model> point_models(const Model& base, const std::vector<SweepAxis>& axes,
                                std::vector<SweepPoint>* points = nullptr) {
  require(!axes.empty() && axes.size() <= 2, "sweep: give one or two parameters");
  std::size_t count = 1;
  for (const auto& a : axes) {
    require(!a.values.empty(), "sweep: parameter '" + a.name + "' has no values");
    (void)get_parameter(base, a.name);  // unknown names fail here, before any work
    count *= a.values.size();
  }
  std::vector<Model> models;
  models.reserve(count);
  if (points) points->resize(count);
  for (std::size_t k = 0; k < count; ++k) {
    std::vector<double> values(axes.size());
    std::size_t rest = k;
    for (std::size_t a = axes.size(); a-- > 0;) {
      values[a] = axes[a].values[rest % axes[a].values.size()];
      rest /= axes[a].values.size();
    }
    Model m = base;
    for (std::size_t a = 0; a < axes.size(); ++a) set_parameter(m, axes[a].name, values[a]);
    models.push_back(std::move(m));
    if (points) (*points)[k].parameters = std::move(values);
  }
  return models;
}

/// The grid (envelope of the automatic domains) and the points without a domain.
SweepPlan plan_grid(const std::vector<Model>& models, const GridRequest& request, const DomainOptions& domain) {
  SweepPlan plan;
  plan.errors.assign(models.size(), std::string());
  Grid grid = request.grid;
  if (request.auto_x || request.auto_y) {
    bool first = true;
    for (std::size_t k = 0; k < models.size(); ++k) {
      try {
        const Grid g = automatic_domain(FpkModel(models[k], "sweep point " + std::to_string(k)),
                                        grid.x.n, grid.y.n, domain);
        for (int ax = 0; ax < 2; ++ax) {
          if (!(ax == 0 ? request.auto_x : request.auto_y)) continue;
          Axis& dst = ax == 0 ? grid.x : grid.y;
          const Axis& src = ax == 0 ? g.x : g.y;
          dst.min = first ? src.min : std::min(dst.min, src.min);
          dst.max = first ? src.max : std::max(dst.max, src.max);
        }
        first = false;
      } catch (const Error& e) {
        plan.errors[k] = e.what();
      }
    }
    require(!first, "sweep: no point of the sweep has a stationary density (first error: " +
                        plan.errors[0] + ")");
  }
  if (auto why = grid.invalid_reason(); !why.empty()) throw Error(why);
  plan.grid = grid;
  return plan;
}

void check_plan(const SweepPlan& plan, std::size_t count) {
  require(plan.errors.size() == count, "sweep: the plan has " + std::to_string(plan.errors.size()) +
                                           " points, the sweep " + std::to_string(count));
}

/// One symbolic analysis, of the first point with a domain, shared read-only by every
/// thread's cache, so that the factorisations (and results) do not depend on the thread count.
void analyse_points(SweepPlan& plan, const std::vector<Model>& models, const SolveOptions& options) {
  plan.analysis.reset();
  plan.analysis_error.clear();
  if (options.solver != Solver::Direct) return;
  check_plan(plan, models.size());
  for (std::size_t k = 0; k < models.size(); ++k) {
    if (!plan.errors[k].empty()) continue;
    try {
      const bool compact = options.scheme == Scheme::Flux && options.correction_steps > 0;
      auto shared = std::make_shared<DirectSolverCache>();
      shared->analyze(assemble_operator(FpkModel(models[k]), plan.grid, compact ? Scheme::Flux2 : options.scheme),
                      options.ordering == Ordering::Auto ? Ordering::Metis : options.ordering);
      plan.analysis = std::move(shared);
      return;
    } catch (const Error& e) {
      plan.analysis_error = e.what();
    }
  }
}

}  // namespace

SweepPlan plan_sweep(const Model& base, const std::vector<SweepAxis>& axes, const GridRequest& request,
                     const SweepOptions& options) {
  if (auto why = options.invalid_reason(); !why.empty()) throw Error("sweep: " + why);
  return plan_grid(point_models(base, axes), request, options.domain);
}

void analyse_sweep(SweepPlan& plan, const Model& base, const std::vector<SweepAxis>& axes,
                   const SweepOptions& options) {
  analyse_points(plan, point_models(base, axes), options.solve);
}

SweepResult sweep(const Model& base, const std::vector<SweepAxis>& axes, const GridRequest& request,
                  const SweepOptions& sweep_options) {
  const auto t0 = std::chrono::steady_clock::now();
  if (auto why = sweep_options.invalid_reason(); !why.empty()) throw Error("sweep: " + why);
  SolveOptions options = sweep_options.solve;
  options.sor.progress = nullptr;  // the sweep reports points
  options.log = nullptr;
  const DomainOptions& domain = sweep_options.domain;
  const double tol = domain.boundary_mass_tolerance;
  SweepResult out;
  out.axes = axes;
  const std::vector<Model> models = point_models(base, axes, &out.points);
  const std::size_t count = models.size();
  // a given plan is copied (a grid, the errors and a shared pointer) to add the analysis if it has none
  SweepPlan plan = sweep_options.plan ? *sweep_options.plan : plan_grid(models, request, domain);
  check_plan(plan, count);
  if (!plan.analysis) analyse_points(plan, models, options);
  for (std::size_t k = 0; k < count; ++k) out.points[k].error = plan.errors[k];
  const Grid& grid = plan.grid;
  out.grid = grid;
  const bool have_analysis = plan.analysis != nullptr;
  const std::string& cache_error = plan.analysis_error;
  const std::size_t block_first = std::min(sweep_options.block_first, count);
  const std::size_t block_last =
      sweep_options.block_last == 0 ? count : std::clamp(sweep_options.block_last, block_first, count);
  for (std::size_t k = 0; k < count; ++k)
    if (k < block_first || k >= block_last) out.points[k].error = "outside the block";
  vehs::detail::ProgressCounter prog(sweep_options.progress, "fpk sweep",
                                     static_cast<long long>(block_last - block_first));
  int threads_used = 1;
  // every thread factorises its own matrix: no more threads than the memory limit holds
  const double per_solve = estimated_solve_bytes(grid.size(), options);
  const int memory_threads = static_cast<int>(
      std::max(1.0, std::floor(vehs::detail::default_memory_limit(options.memory_limit) / per_solve)));
  const int threads = std::min(vehs::max_threads(), memory_threads);
#pragma omp parallel num_threads(threads)
  {
#ifdef _OPENMP
#pragma omp single
    threads_used = omp_get_num_threads();
#endif
    DirectSolverCache cache;
    if (have_analysis) cache.share_analysis(*plan.analysis);
#pragma omp for schedule(dynamic, 1)
    for (long long kk = static_cast<long long>(block_first); kk < static_cast<long long>(block_last); ++kk) {
      const auto k = static_cast<std::size_t>(kk);
      SweepPoint& pt = out.points[k];
      if (pt.error.empty()) {
        try {
          if (options.solver == Solver::Direct && !have_analysis) throw Error(cache_error);
          const FpkModel fm(models[k], "sweep point " + std::to_string(k));
          StationaryResult r = solve_stationary(fm, grid, options, have_analysis ? &cache : nullptr);
          // The shared grid is the envelope of all points' domains: a narrow density on it may be
          // under-resolved and leak mass to the edges although the point is fine on its own
          // automatic domain (same cell counts), where it is solved again.
          const bool automatic = request.auto_x || request.auto_y;
          if (automatic && (std::abs(r.boundary_signed_mass()) > tol || r.summary.negative_mass < -1e-3)) {
            r = solve_with_domain(fm, request, options, domain);
            pt.own_domain = true;
          }
          pt.moments = r.moments;
          pt.identities = r.identities;
          pt.boundary_mass = r.boundary_mass;
          pt.residual = r.summary.residual;
          pt.wells = r.wells;
          if (std::abs(r.boundary_signed_mass()) > tol)
            pt.error = "boundary mass " + std::to_string(r.boundary_signed_mass()) + " exceeds " +
                       std::to_string(tol) + " (enlarge the grid)";
          else if (r.summary.negative_mass < -1e-3)
            pt.error = "negative density of total mass " + std::to_string(r.summary.negative_mass) +
                       ": the grid does not resolve the density (use more cells)";
        } catch (const Error& e) {
          pt.error = e.what();
        } catch (const std::exception& e) {
          pt.error = std::string("internal error: ") + e.what();
        }
      }
      prog.advance();
    }
  }
  prog.finish();
  out.threads = threads_used;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace vehs::fpk

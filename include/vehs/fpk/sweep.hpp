#pragma once
// Parameter sweeps of the stationary FPK: one or two model parameters (by the names of
// vehs/core/parameters.hpp) over values, all points on one grid and one symbolic factorisation.
#include <memory>
#include <string>
#include <vector>

#include "vehs/core/model.hpp"
#include "vehs/core/progress.hpp"
#include "vehs/fpk/solve.hpp"

namespace vehs::fpk {

struct SweepAxis {
  std::string name;
  std::vector<double> values;
};

struct SweepPoint {
  std::vector<double> parameters;  ///< one value per sweep axis
  Moments moments;
  Identities identities;
  double boundary_mass = 0.0;      ///< StationaryResult::boundary_mass (≥ 0)
  double residual = 0.0;
  std::vector<Well> wells;
  /// Solved on its own automatic domain (same cell counts) because the shared grid did not
  /// resolve it (boundary mass above the tolerance or negative density).
  bool own_domain = false;
  std::string error;               ///< non-empty when this point could not be solved
};

struct SweepResult {
  std::vector<SweepAxis> axes;
  Grid grid;                       ///< the one grid shared by all points
  std::vector<SweepPoint> points;  ///< product grid, last axis fastest
  double seconds = 0.0;
  int threads = 1;
};

/// What every point (and every block of points) of a sweep shares: the grid — automatic axes
/// of the request become the envelope of the automatic domains of all points — the points that
/// have no automatic domain, and, for the direct solver, one symbolic analysis (of the first
/// point that has a domain) that every factorisation starts from. A plan made once (e.g. on the
/// client of a cluster, grid and errors shipped as numbers, the analysis redone once per worker)
/// makes blocks of points solved apart equal the same points of the whole sweep.
struct SweepPlan {
  Grid grid;
  std::vector<std::string> errors;  ///< per point (product order): why it has no domain; empty: fine
  /// The shared symbolic analysis (analyse_sweep; read-only once made); null: not made.
  std::shared_ptr<const DirectSolverCache> analysis;
  std::string analysis_error;       ///< why no point could be analysed
};

/// Solves the stationary FPK for every point of the product of `axes` (at most 2) on one
/// grid: automatic axes of `request` become the envelope of the automatic domains of all
/// points. Points run in parallel (OpenMP, each thread with its own factorisation cache, all
/// analysed on the same matrix), so results do not depend on the thread count. A point that
/// fails (non-confining potential, too much boundary mass) records its error and the sweep
/// goes on.
struct SweepOptions {
  SolveOptions solve;
  DomainOptions domain;
  ProgressCallback progress;  ///< task "fpk sweep", one event per point; empty: none
  /// Solve only the points [block_first, block_last) of the product (block_last 0: to the end);
  /// the others get the error "outside the block". The grid and the shared symbolic analysis
  /// still come from every point, so a block's points equal the same points of the whole sweep
  /// (a sweep split over processes or machines and merged point by point: vehs.dask.sweep).
  std::size_t block_first = 0, block_last = 0;
  /// A plan of this sweep (plan_sweep of the same base, axes, request and options); null: made
  /// here. Without its analysis (direct solver), the analysis is made here.
  const SweepPlan* plan = nullptr;
  std::string invalid_reason() const;
};
SweepResult sweep(const Model& base, const std::vector<SweepAxis>& axes, const GridRequest& request,
                  const SweepOptions& options = {});

/// The grid and the per-point domain errors of a sweep (no analysis: cheap to ship); throws
/// when no point has a stationary density.
SweepPlan plan_sweep(const Model& base, const std::vector<SweepAxis>& axes, const GridRequest& request,
                     const SweepOptions& options = {});
/// Adds the shared symbolic analysis to `plan` (direct solver; nothing otherwise).
void analyse_sweep(SweepPlan& plan, const Model& base, const std::vector<SweepAxis>& axes,
                   const SweepOptions& options = {});

}  // namespace vehs::fpk

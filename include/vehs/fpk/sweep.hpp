#pragma once
// Parameter sweeps of the stationary FPK: one or two model parameters (by the names of
// vehs/core/parameters.hpp) over values, all points on one grid and one symbolic factorisation.
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
  double boundary_mass = 0.0;
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
  std::string invalid_reason() const;
};
SweepResult sweep(const Model& base, const std::vector<SweepAxis>& axes, const GridRequest& request,
                  const SweepOptions& options = {});

}  // namespace vehs::fpk

#pragma once
// Solving the stationary FPK equation (stationary.hpp describes the schemes and solvers): options,
// results, automatic domains, the direct solver's reusable factorisation.
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "vehs/conventions.hpp"
#include "vehs/core/enum_names.hpp"
#include "vehs/core/progress.hpp"
#include "vehs/fpk/assemble.hpp"
#include "vehs/fpk/fpk_model.hpp"
#include "vehs/fpk/grid.hpp"

namespace vehs::fpk {

enum class Solver { Direct, Sor, Bicgstab };
inline constexpr EnumNames<Solver, 3> kSolverNames{
    {{Solver::Direct, "direct"}, {Solver::Sor, "sor"}, {Solver::Bicgstab, "bicgstab"}}};


struct SorOptions {
  double alpha = 0.01;          ///< relaxation factor (the paper: 0.01)
  double tolerance = 1e-5;      ///< on max|Δp| / max p per sweep (the paper: 1e-5)
  long max_iterations = 1000000;
  int normalize_every = 10;     ///< sweeps between normalisations (the paper: 10)
  /// Task "fpk sor", one unit per sweep (reported every 100 sweeps); empty: none. Sweeps over
  /// parameters clear it (their own progress counts points).
  ProgressCallback progress;
  std::string invalid_reason() const;
};

struct IterativeOptions {
  double tolerance = 1e-10;     ///< relative residual of the bordered system
  int max_iterations = 20000;
  double drop_tolerance = 1e-4; ///< ILUT drop tolerance
  int fill_factor = 20;         ///< ILUT fill factor
  std::string invalid_reason() const;
};

/// Fill-reducing ordering of the direct solver: METIS nested dissection (least fill, costly
/// analysis: worth it when one analysis serves many factorisations) or AMD (cheap analysis,
/// ~25 % more fill). Auto: AMD for single solves, METIS for sweeps (bench/bench_fpk.cpp).
enum class Ordering { Auto, Metis, Amd };
inline constexpr EnumNames<Ordering, 3> kOrderingNames{
    {{Ordering::Auto, "auto"}, {Ordering::Metis, "metis"}, {Ordering::Amd, "amd"}}};

struct SolveOptions {
  Scheme scheme = Scheme::Flux;
  Solver solver = Solver::Direct;
  Ordering ordering = Ordering::Auto;
  /// Direct solver with Scheme::Flux: factorise the compact flux2 operator and take this many
  /// defect-correction steps p ← p + L⁻¹(b − A p) towards the fourth-order operator A
  /// (2 steps reach A's own solution to ~1 % of the discretisation error on resolved grids, at
  /// ~1/2 the cost of factorising A); 0 factorises A itself.
  int correction_steps = 2;
  SorOptions sor;
  IterativeOptions iterative;
  /// Bytes a solve may take (estimated_solve_bytes; 0: 3/4 of physical memory); a larger grid is
  /// refused before anything is allocated.
  double memory_limit = 0.0;
  /// Lines for a person waiting on the direct solver, whose factorisation reports no progress
  /// from inside UMFPACK: one line as each phase starts ("factorising 1000x1000 cells
  /// (symbolic)...", "(numeric)...") and one with their seconds and the factor's size. Empty:
  /// none. Sweeps clear it (their progress counts points).
  std::function<void(const std::string&)> log;
  std::string invalid_reason() const;
};

/// Peak memory of one solve on `cells` cells, measured (max RSS, GCC 12, UMFPACK with METIS, the
/// paper's model): direct solver N·(680 + 27.5·log2 N) bytes (1.13 kB per cell at 300², 1.23 kB
/// at 1000²), SOR 300 bytes per cell, BiCGSTAB with ILUT the direct solver's.
double estimated_solve_bytes(std::size_t cells, const SolveOptions& options);
/// Seconds one direct solve on `cells` cells takes on one idle core (README's bench_fpk figures:
/// 1.1 s at 400², 10-20 s at 1000²; nested dissection's N^1.5), to say before a long
/// factorisation starts; 0 for the iterative solvers (they report progress themselves).
double estimated_solve_seconds(std::size_t cells, const SolveOptions& options);

/// What a solve did.
struct SolveSummary {
  std::string solver, scheme;
  double assemble_seconds = 0.0, solve_seconds = 0.0;  ///< wall clock
  long iterations = 0;              ///< SOR sweeps / BiCGSTAB iterations / defect corrections
  bool converged = true;            ///< stopping rule met (always true for direct)
  std::size_t normalization_row = 0;
  int normalization_attempts = 1;   ///< 2 when the first guess of the maximum was poor
  double residual = 0.0;            ///< max_k |(A p)_k| / max_k (|A||p|)_k, all equations
  double dropped_equation_residual = 0.0;  ///< same ratio for the replaced equation alone
  double negative_mass = 0.0;       ///< ∫ min(p, 0) (central schemes can undershoot)
  double min_density_ratio = 0.0;   ///< min p / max p
  std::size_t nonzeros = 0;         ///< of A
  std::size_t factor_nonzeros = 0;  ///< of L + U (direct) or the ILU factor
  double factor_megabytes = 0.0;
};


/// A probability well of the potential U(x) = −∫₀ˣ b2(s, 0) ds: a local minimum and the mass
/// between the neighbouring maxima (or the domain ends).
struct Well {
  double x_min = 0.0;            ///< location of the minimum
  double potential = 0.0;        ///< U at the minimum
  double lo = 0.0, hi = 0.0;     ///< well range (maxima or domain ends)
  double mass = 0.0;             ///< ∫_lo^hi p(x) dx
};

struct Moments {
  double ex = 0.0, ey = 0.0, exx = 0.0, eyy = 0.0, exy = 0.0;
  double x_b2 = 0.0;    ///< E[X·b2(X, Y)]
  double y_b2 = 0.0;    ///< E[Y·b2(X, Y)]
  double a22 = 0.0;     ///< E[a22(X, Y)]
  double mass = 0.0;    ///< ∫∫ p (1 after normalisation)
};

/// Exact stationary identities (any model, from d/dt E[·] = 0) evaluated on the solution:
/// E[XY] = 0; virial E[Y²] + E[X·b2] = 0; energy balance E[Y·b2] + ½E[a22] = 0. Each is
/// reported as a ratio to its natural scale (sqrt(E[X²]E[Y²]), E[Y²], ½E[a22]).
struct Identities {
  double xy = 0.0, virial = 0.0, energy = 0.0;
};

struct StationaryResult {
  Grid grid;
  std::vector<double> density;     ///< p at cell centres, k = i·ny + j, ∫p = 1
  std::vector<double> marginal_x;  ///< p(x_i) = Σ_j p_ij hy
  std::vector<double> marginal_y;  ///< p(y_j) = Σ_i p_ij hx
  Moments moments;
  Identities identities;
  /// Probability mass in the outermost ring of cells: Σ max(p, 0)·area (≥ 0; the central
  /// scheme's undershoot there, ±1e-9 where the density has vanished, is boundary_undershoot).
  double boundary_mass = 0.0;
  double boundary_undershoot = 0.0;  ///< Σ min(p, 0)·area over the ring (≤ 0)
  double boundary_mass_x = 0.0;      ///< signed Σ p·area in the first/last columns in x
  double boundary_mass_y = 0.0;      ///< … in the first/last rows in y
  /// Signed Σ p·area over the ring: what the domain control tests (an undershoot on the edges
  /// is an edge error as well as mass).
  double boundary_signed_mass() const { return boundary_mass + boundary_undershoot; }
  std::vector<Well> wells;
  SolveSummary summary;
  bool auto_domain = false;
  int domain_enlargements = 0;
  int refinements = 0;  ///< times the cells per axis were doubled because the grid did not resolve the model
};


/// Automatic domain from the potential and the noise: x spans where the local-equilibrium
/// log-density Φ(x) = ∫ U'(s)/T(s) ds stays within K = `log_density_drop` (natural-log units) of
/// its minimum (T = local temperature, FpkModel::temperature; exact for the damping
/// β(x) = β0(1 + Q x²/D), conservative for constant β where the true tails are lighter); y is
/// symmetric with y_max = max(sqrt(2·K·T_max), sqrt(2·ΔU_max)) so it grows with x_max when
/// a22 grows with x. Axis sizes come from `nx`, `ny`. `boundary_mass_tolerance` is the check of
/// solve_with_domain and sweep.
struct DomainOptions {
  double log_density_drop = 25.0;  ///< K: density ratio e^−K at the domain edge
  /// Largest probability mass allowed in the outermost ring of cells (the contract's 1e-6).
  double boundary_mass_tolerance = conventions::fpk_boundary_mass_tolerance;
  /// solve_with_domain doubles the cells per axis of an under-resolved grid (automatic axes
  /// only) while they stay within this; 0: never (an error says how many cells are needed).
  int max_cells = 800;
  std::string invalid_reason() const;
};
Grid automatic_domain(const FpkModel& model, int nx, int ny, const DomainOptions& options = {});


class DirectSolverCache;
namespace detail {
struct SolverAccess;  // the solvers' access to a cache's factorisation (solve.cpp)
}  // namespace detail

/// A solve whose density has no positive mass: the grid cannot carry the model (far too few
/// cells, or a domain that misses the density); solve_with_domain treats it as unresolved.
class SolveBreakdown : public Error {
 public:
  using Error::Error;
};

/// Assembles and solves on `grid`; fills density, marginals, moments, identities, wells.
/// `reuse` (optional) is a factorisation cache for repeated solves on one grid (sweeps).
/// Throws SolveBreakdown when the solution has no positive mass.
StationaryResult solve_stationary(const FpkModel& model, const Grid& grid,
                                  const SolveOptions& options, DirectSolverCache* reuse = nullptr);


/// The front end used by the executable: automatic axes are computed, then the solve is
/// checked against the boundary-mass tolerance (an automatic axis holding too much mass is
/// recomputed with 8 more e-folds of density drop, up to 6 times; a given axis is an error) and
/// for undershoots (a negative total of more than 1e-3). A grid that does not resolve the
/// model shows as an undershoot or as boundary mass that does not fall when the domain is
/// enlarged (the cells grow with it): the cells per axis are then doubled (up to
/// DomainOptions::max_cells, StationaryResult::refinements), or the error names the cells
/// needed. Smaller undershoots are reported in SolveSummary::negative_mass.
StationaryResult solve_with_domain(const FpkModel& model, const GridRequest& request,
                                   const SolveOptions& options, const DomainOptions& domain = {});

/// Moments, marginals, wells, boundary mass and identities of a density on a grid (used by
/// the solvers; exposed for tests and for comparing densities).
void analyse_density(const FpkModel& model, StationaryResult& result);

/// Wells of the potential over [lo, hi].
std::vector<Well> find_wells(const FpkModel& model, double lo, double hi);


/// Keeps one UMFPACK symbolic analysis (done on the first matrix it sees) for repeated
/// factorisations of matrices with the same pattern. One per thread (numeric factors are
/// per cache; a symbolic analysis may be shared, see share_analysis).
class DirectSolverCache {
 public:
  DirectSolverCache();
  ~DirectSolverCache();
  DirectSolverCache(const DirectSolverCache&) = delete;
  DirectSolverCache& operator=(const DirectSolverCache&) = delete;
  /// Analyses `pattern_matrix` now (so that every thread starts from the same analysis).
  void analyze(const SparseMatrix& pattern_matrix, Ordering ordering);
  /// Uses `other`'s analysis read-only (it must outlive this cache). Sharing one analysis makes
  /// sweeps independent of the thread count even with METIS, whose orderings may differ
  /// between concurrent calls.
  void share_analysis(const DirectSolverCache& other);
  struct Impl;  ///< UMFPACK's symbolic and numeric objects (src/fpk/solve.cpp)

 private:
  friend struct detail::SolverAccess;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vehs::fpk

#pragma once
// Stationary Fokker–Planck equation of the harvester model on a finite-difference grid.
//
// Equation (Itô, conventions.hpp; a22 is the variance rate, hence the ½):
//     0 = −∂x(y p) − ∂y(b2 p) + ½ ∂²y(a22 p),      ∫∫ p dx dy = 1,
// for dX = Y dt, dY = b2(X, Y) dt + sqrt(a22(X, Y)) dB. b2 may hold every drift term a model
// file can hold except the recorded drive `u` (monomials x^a·y^b, sign(y), y·|y|) plus the
// x-only force of the `impact_stop` effect; a22 may hold monomials in x and y. Effects that
// make (X, Y) non-Markov or time-dependent (harmonic_forcing, electromechanical_coupling,
// colored_noise) have no stationary 2-D FPK and are rejected.
//
// Grid: cell-centred (conventions.hpp): nx × ny cells over [x.min, x.max] × [y.min, y.max];
// unknown p_k is the density at the centre of cell (i, j), k = i·ny + j; integrals use the
// midpoint rule. All schemes are second order in h (observed order 2.0 on the exact Q = 0 test):
//  * Scheme::Flux (default) — conservative finite volumes. Face fluxes
//        Jx(i+½, j) = y_j·p(i+½, j),   p(i+½) = (−p_i−1 + 7p_i + 7p_i+1 − p_i+2)/12
//                     (fourth-order interpolation; (p_i + p_i+1)/2 on the faces next to the
//                     outer ones, where the density is negligible),
//        Jy(i, j+½) = b2(x_i, y_j+½)·(p_ij + p_i,j+1)/2 − (a22_i,j+1·p_i,j+1 − a22_ij·p_ij)/(2 hy),
//    zero flux through the outer faces. Every column of the matrix sums to zero (up to
//    rounding), so total mass is conserved exactly and the equation dropped for the
//    normalisation row is implied by the others (its residual is reported as a check).
//    Why this default: x is pure advection (no diffusion) and the wells are narrow in x, so the
//    x-flux error dominates; the fourth-order x-flux cuts the L1 error 4× at 400² (1.3e-4 vs
//    5.2e-4) for about 2× the factorisation cost — cheaper than the 800² grid flux2 needs for
//    the same accuracy (8× the cost). The y-error stays O(h²), hence observed order 2.
//    Central fluxes are not monotone: on grids that do not resolve the density they undershoot
//    (SolveSummary::negative_mass); first-order upwinding would avoid it at the price of a
//    visible bias, and exponential fitting in y (Scharfetter–Gummel) was tried and rejected:
//    its O(z²) artificial diffusion (z = 2 b2 h / a22 ≈ 1 here) gave 2e-2 L1 at 400².
//    The direct solver does not factorise this 7-point operator by default: it factorises the
//    compact flux2 operator and applies two defect-correction steps (SolveOptions::
//    correction_steps; measured at 400²: L1 1.326e-4 after one step, 1.312e-4 after two, the
//    same as the exact solve of the 7-point system). On unresolved grids (≲ 100² here) the
//    correction can amplify grid-scale modes; the undershoot check reports that.
//  * Scheme::Flux2 — the same with (p_i + p_i+1)/2 in x: compact 5-point stencil, fastest.
//  * Scheme::Central — the paper's Eq. 35 with the *correct* central differences
//    (p_i+1 − p_i−1)/(2h) applied to the expanded (non-conservative) Eq. 32,
//        −y ∂x p − (∂y b2) p − b2 ∂y p + ½ a22 ∂²y p + (∂y a22) ∂y p + ½ (∂²y a22) p = 0,
//    with p = 0 outside the grid (the paper states no boundary condition). Not conservative:
//    the dropped equation's residual is O(h²), not zero. Cannot represent sign(y) (its
//    y-derivative is a delta) and rejects it.
//  * Scheme::PaperLiteral — Eq. 35 exactly as printed, first derivatives (p_i+1 − p_i−1)/h
//    without the factor ½. This doubles the advection terms (in x and y) relative to the
//    diffusion and to the zeroth-order (∂y b2)·p term: an inconsistent scheme, kept only to show
//    what the misprint does (L1 error > 0.05 that does not shrink with h, see the tests).
//
// Solvers:
//  * Solver::Direct — sparse LU (SuiteSparse UMFPACK, symmetric strategy, METIS or AMD
//    ordering) of the singular system
//    made regular by replacing the equation of one cell r (the density maximum; first guessed
//    at the deepest well of the potential at y ≈ 0, moved and re-solved if the guess holds
//    less than 1 % of the maximum) by s·p_r = s, s = mean |diagonal|; then p is normalised to
//    ∫p = 1 with the midpoint rule. The row keeps its pattern (explicit zeros) so that sweeps
//    can reuse one symbolic factorisation.
//  * Solver::Sor — the paper's iteration (Eq. 37): Gauss–Seidel sweeps in the paper's order
//    (x index fastest) relaxed by alpha, negative values set to 0, normalisation every
//    `normalize_every` sweeps, stopped when max|p_new − p_old| / max p < tolerance. With
//    alpha = 0.01 the change per sweep is ~alpha × the error, so the rule either fires far
//    from the solution or never (the paper's own 50² case: not after 10⁶ sweeps); the summary
//    reports the true residual so that this is visible.
//  * Solver::Bicgstab — BiCGSTAB with an incomplete-LU (ILUT) preconditioner on the same
//    bordered system, for grids too large to factorise; stops at a relative residual of
//    `iterative.tolerance`.
//
// Tolerances: the contract allows at most conventions::fpk_boundary_mass_tolerance (1e-6) of
// the mass in the outermost ring of cells of a user-given domain; `boundary_mass_tolerance`
// can raise it explicitly (e.g. to reproduce the paper's [−1.6, 1.6]² grid).
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/SparseCore>

#include "vehs/conventions.hpp"
#include "vehs/core/enum_names.hpp"
#include "vehs/core/model.hpp"
#include "vehs/core/progress.hpp"

namespace vehs::fpk {

enum class Scheme { Flux, Flux2, Central, PaperLiteral };
inline constexpr EnumNames<Scheme, 4> kSchemeNames{{{Scheme::Flux, "flux"},
                                                    {Scheme::Flux2, "flux2"},
                                                    {Scheme::Central, "central"},
                                                    {Scheme::PaperLiteral, "paper_literal"}}};

enum class Solver { Direct, Sor, Bicgstab };
inline constexpr EnumNames<Solver, 3> kSolverNames{
    {{Solver::Direct, "direct"}, {Solver::Sor, "sor"}, {Solver::Bicgstab, "bicgstab"}}};

/// One axis of a cell-centred grid: n cells over [min, max].
struct Axis {
  double min = -1.0, max = 1.0;
  int n = 100;
  double h() const { return (max - min) / n; }
  double center(int i) const { return min + (i + 0.5) * h(); }
  double face(int i) const { return min + i * h(); }  ///< i = 0..n
};

struct Grid {
  Axis x, y;
  std::size_t size() const { return static_cast<std::size_t>(x.n) * static_cast<std::size_t>(y.n); }
  std::size_t index(int i, int j) const {
    return static_cast<std::size_t>(i) * static_cast<std::size_t>(y.n) + static_cast<std::size_t>(j);
  }
  double cell_area() const { return x.h() * y.h(); }
  /// Empty when valid (finite, min < max, n >= 3), else a one-line reason.
  std::string invalid_reason() const;
};

/// The drift and diffusion as the FPK sees them: model terms plus the impact_stop force.
/// The constructor checks that a stationary 2-D FPK exists for the model (no `u` term, no
/// dynamic effect other than impact_stop, finite coefficients, a confining potential,
/// dissipation in y) and throws vehs::Error naming `where` and the reason otherwise.
class FpkModel {
 public:
  explicit FpkModel(const Model& model, const std::string& where = "model");

  double b2(double x, double y) const;        ///< full drift of dY
  double db2_dy(double x, double y) const;    ///< ∂b2/∂y (0 a.e. for sign(y))
  double a22(double x, double y) const;       ///< variance rate of dY
  double da22_dy(double x, double y) const;
  double d2a22_dy2(double x, double y) const;
  /// U'(x) = −b2(x, 0): the restoring force of the x-only part of the drift (incl. stops).
  double restoring_force(double x) const;
  /// U(x) = ∫₀ˣ U'(s) ds (exact for polynomials and stops).
  double potential(double x) const;
  /// Effective damping at displacement x for velocities of size v: −(b2(x,v) − b2(x,−v))/(2v).
  double damping(double x, double v) const;
  /// Local effective temperature a22(x, 0) / (2·β_eff), with β_eff the damping at the
  /// self-consistent velocity scale v = sqrt(T) (exact for linear damping).
  double temperature(double x) const;
  bool has_sign_y() const { return has_sign_y_; }
  const Model& model() const { return model_; }
  const std::string& where() const { return where_; }

 private:
  Model model_;
  std::string where_;
  double k_stop_ = 0.0, gap_ = 0.0, gap_neg_ = 0.0;
  bool has_stop_ = false, has_sign_y_ = false;
};

/// Sparse stationary FPK operator A (A p = 0) in compressed-column storage with the fixed
/// 5-point pattern (W, S, C, N, E neighbours of every cell), so that all models on one grid
/// share one pattern. Throws vehs::Error when a coefficient is not finite on the grid or a22
/// is negative somewhere (naming the point).
using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
SparseMatrix assemble_operator(const FpkModel& model, const Grid& grid, Scheme scheme);

struct SorOptions {
  double alpha = 0.01;          ///< relaxation factor (the paper: 0.01)
  double tolerance = 1e-5;      ///< on max|Δp| / max p per sweep (the paper: 1e-5)
  long max_iterations = 1000000;
  int normalize_every = 10;     ///< sweeps between normalisations (the paper: 10)
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
  std::string invalid_reason() const;
};

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
  double boundary_mass = 0.0;      ///< mass in the outermost ring of cells
  double boundary_mass_x = 0.0;    ///< … in the first/last columns in x
  double boundary_mass_y = 0.0;    ///< … in the first/last rows in y
  std::vector<Well> wells;
  SolveSummary summary;
  bool auto_domain = false;
  int domain_enlargements = 0;
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
  std::string invalid_reason() const;
};
Grid automatic_domain(const FpkModel& model, int nx, int ny, const DomainOptions& options = {});

/// Assembles and solves on `grid`; fills density, marginals, moments, identities, wells.
/// `reuse` (optional) is a factorisation cache for repeated solves on one grid (sweeps).
class DirectSolverCache;
StationaryResult solve_stationary(const FpkModel& model, const Grid& grid,
                                  const SolveOptions& options, DirectSolverCache* reuse = nullptr);

/// Which axes of a grid are chosen automatically.
struct GridRequest {
  bool auto_x = true, auto_y = true;
  Grid grid;  ///< fixed axes as given; for automatic axes only n is used
};

/// The front end used by the executable: automatic axes are computed, then the solve is
/// checked against the boundary-mass tolerance (an automatic axis holding too much mass is
/// recomputed with 8 more e-folds of density drop, up to 6 times; a given axis is an error) and
/// for undershoots (a negative total of more than 1e-3 means the grid does not resolve the
/// density: an error; smaller undershoots are reported in SolveSummary::negative_mass).
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
  struct Impl;
  Impl* impl() { return impl_; }

 private:
  Impl* impl_;
};

// ---- sweeps -------------------------------------------------------------------------------

/// A model parameter by name: "beta" (−drift[y]), "k<i>" (−drift[x^i]), "2D" (diffusion[1]),
/// "2Q" (diffusion[x^2]), "D", "Q" (halves of those), "drift[<term>]", "diffusion[<term>]",
/// "impact_stop.<param>". Throws vehs::Error for unknown names.
void set_model_parameter(Model& model, const std::string& name, double value);
double get_model_parameter(const Model& model, const std::string& name);

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
  std::string invalid_reason() const;
};
SweepResult sweep(const Model& base, const std::vector<SweepAxis>& axes, const GridRequest& request,
                  const SweepOptions& options = {});

}  // namespace vehs::fpk

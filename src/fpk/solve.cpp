// Solvers of the stationary FPK system: UMFPACK direct solve with a normalisation row, the
// paper's relaxed Gauss–Seidel (SOR), and ILUT-preconditioned BiCGSTAB.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <memory>
#include <sstream>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>
#include <suitesparse/umfpack.h>

#include "vehs/core/detail/progress_counter.hpp"
#include "vehs/core/detail/format.hpp"
#include "vehs/core/detail/memory.hpp"
#include "vehs/core/error.hpp"
#include "vehs/fpk/solve.hpp"

namespace vehs::fpk {

std::string SorOptions::invalid_reason() const {
  if (!(alpha > 0.0 && alpha < 2.0)) return "sor.alpha must be in (0, 2)";
  if (!(tolerance > 0.0)) return "sor.tolerance must be > 0";
  if (max_iterations < 1) return "sor.max_iterations must be >= 1";
  if (normalize_every < 1) return "sor.normalize_every must be >= 1";
  return "";
}

std::string IterativeOptions::invalid_reason() const {
  if (!(tolerance > 0.0 && tolerance < 1.0)) return "iterative.tolerance must be in (0, 1)";
  if (max_iterations < 1) return "iterative.max_iterations must be >= 1";
  if (!(drop_tolerance >= 0.0)) return "iterative.drop_tolerance must be >= 0";
  if (fill_factor < 1) return "iterative.fill_factor must be >= 1";
  return "";
}

std::string SolveOptions::invalid_reason() const {
  if (correction_steps < 0 || correction_steps > 100) return "correction_steps must be in 0..100";
  if (solver == Solver::Sor) return sor.invalid_reason();
  if (solver == Solver::Bicgstab) return iterative.invalid_reason();
  return "";
}

// ---- UMFPACK wrapper ------------------------------------------------------------------------
// UMFPACK's dense kernels call the system BLAS, and Debian's fast one (libopenblas0-serial,
// which scripts/install-deps.sh installs) is built without locking: two threads inside it at
// once share its buffers and get silently perturbed results (measured: a parallel sweep gave
// different E[Y²] on every run, up to 1e-7 relative, where one thread is bitwise
// reproducible). So every UMFPACK call holds this lock; a parallel sweep still overlaps the
// assembly and post-processing of its points.
static std::mutex& blas_mutex() {
  static std::mutex m;
  return m;
}

struct DirectSolverCache::Impl {
  void* symbolic = nullptr;
  void* numeric = nullptr;
  bool owns_symbolic = true;  ///< false: shared read-only from another cache
  double control[UMFPACK_CONTROL];
  double info[UMFPACK_INFO];
  int n = -1;
  std::size_t nnz = 0;

  Ordering ordering = Ordering::Amd;

  Impl() {
    umfpack_di_defaults(control);
    // The operator is structurally symmetric: order A + Aᵀ and prefer diagonal pivots.
    control[UMFPACK_STRATEGY] = UMFPACK_STRATEGY_SYMMETRIC;
    set_ordering(Ordering::Amd);
  }
  void set_ordering(Ordering o) {
    if (o != ordering && symbolic) release();
    ordering = o;
    control[UMFPACK_ORDERING] = o == Ordering::Metis ? UMFPACK_ORDERING_METIS : UMFPACK_ORDERING_AMD;  // Auto → AMD
  }
  ~Impl() { release(); }
  void release_numeric() {
    if (numeric) umfpack_di_free_numeric(&numeric);
    numeric = nullptr;
  }
  void release() {
    release_numeric();
    if (symbolic && owns_symbolic) umfpack_di_free_symbolic(&symbolic);
    symbolic = nullptr;
    owns_symbolic = true;
  }
  bool matches(const SparseMatrix& A) const {
    return symbolic && A.rows() == n && static_cast<std::size_t>(A.nonZeros()) == nnz;
  }
  void analyze(const SparseMatrix& A) {
    release();
    n = static_cast<int>(A.rows());
    nnz = static_cast<std::size_t>(A.nonZeros());
    std::lock_guard<std::mutex> lock(blas_mutex());
    const int status = umfpack_di_symbolic(n, n, A.outerIndexPtr(), A.innerIndexPtr(), A.valuePtr(),
                                           &symbolic, control, info);
    if (status != UMFPACK_OK) {
      symbolic = nullptr;
      throw Error("UMFPACK symbolic analysis failed (status " + std::to_string(status) + ")" +
                  (status == UMFPACK_ERROR_out_of_memory ? ": out of memory" : ""));
    }
  }
  /// Factorises A (analysing it first when no analysis of this pattern exists).
  void factorize(const SparseMatrix& A) {
    if (!matches(A)) analyze(A);
    release_numeric();
    std::lock_guard<std::mutex> lock(blas_mutex());
    const int status = umfpack_di_numeric(A.outerIndexPtr(), A.innerIndexPtr(), A.valuePtr(),
                                          symbolic, &numeric, control, info);
    if (status == UMFPACK_WARNING_singular_matrix)
      throw Error("the FPK system with its normalisation row is singular (the discrete operator "
                  "has more than one stationary density: e.g. disconnected regions of the grid)");
    if (status != UMFPACK_OK)
      throw Error("UMFPACK factorisation failed (status " + std::to_string(status) + ")" +
                  (status == UMFPACK_ERROR_out_of_memory ? ": out of memory" : ""));
  }
  void solve(const SparseMatrix& A, const double* b, double* x) {
    std::lock_guard<std::mutex> lock(blas_mutex());
    const int status = umfpack_di_solve(UMFPACK_A, A.outerIndexPtr(), A.innerIndexPtr(),
                                        A.valuePtr(), x, b, numeric, control, info);
    if (status != UMFPACK_OK && status != UMFPACK_WARNING_singular_matrix)
      throw Error("UMFPACK solve failed (status " + std::to_string(status) + ")");
  }
  std::size_t factor_nonzeros() const {
    return static_cast<std::size_t>(info[UMFPACK_LNZ] + info[UMFPACK_UNZ]);
  }
  double factor_megabytes() const {
    return info[UMFPACK_NUMERIC_SIZE] * info[UMFPACK_SIZE_OF_UNIT] / 1048576.0;
  }
};

DirectSolverCache::DirectSolverCache() : impl_(std::make_unique<Impl>()) {}
DirectSolverCache::~DirectSolverCache() = default;

namespace detail {
struct SolverAccess {
  static DirectSolverCache::Impl& of(DirectSolverCache& cache) { return *cache.impl_; }
};
}  // namespace detail
void DirectSolverCache::share_analysis(const DirectSolverCache& other) {
  impl_->release();
  impl_->set_ordering(other.impl_->ordering);
  impl_->symbolic = other.impl_->symbolic;  // UMFPACK only reads it in umfpack_di_numeric
  impl_->owns_symbolic = false;
  impl_->n = other.impl_->n;
  impl_->nnz = other.impl_->nnz;
}

void DirectSolverCache::analyze(const SparseMatrix& pattern_matrix, Ordering ordering) {
  impl_->set_ordering(ordering);
  impl_->analyze(pattern_matrix);
}

// ---- helpers --------------------------------------------------------------------------------

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// Cell where the density is expected to peak: the minimum over x-cells of the
/// local-equilibrium log-density Φ(x) = ∫ U'/T, at the y-cell nearest 0.
std::size_t guess_maximum(const FpkModel& model, const Grid& g) {
  double phi = 0.0, best = 0.0;
  int best_i = 0;
  double prev = 0.0;
  for (int i = 0; i < g.x.n; ++i) {
    const double x = g.x.center(i);
    const double t = std::max(model.temperature(x), 1e-300);
    const double integrand = model.restoring_force(x) / t;
    if (i > 0) phi += 0.5 * (integrand + prev) * g.x.h();
    prev = integrand;
    if (i == 0 || phi < best) {
      best = phi;
      best_i = i;
    }
  }
  int best_j = 0;
  for (int j = 1; j < g.y.n; ++j)
    if (std::abs(g.y.center(j)) < std::abs(g.y.center(best_j))) best_j = j;
  return g.index(best_i, best_j);
}

/// Replaces equation r of A by s·p_r = s, keeping the pattern (explicit zeros); returns the
/// original values of that row (in the order of the columns W, S, C, N, E that hold it).
struct SavedRow {
  std::vector<std::pair<double*, double>> entries;
  void restore() {
    for (auto& [ptr, v] : entries) *ptr = v;
  }
};
SavedRow set_normalization_row(SparseMatrix& A, std::size_t r, double s) {
  SavedRow saved;
  const int ri = static_cast<int>(r);
  const int n = static_cast<int>(A.rows());
  // columns that may contain row r: those adjacent in the pattern (their own row lists hold r)
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  double* val = A.valuePtr();
  // the neighbours of r are exactly the rows of column r (symmetric pattern)
  for (int p = outer[ri]; p < outer[ri + 1]; ++p) {
    const int c = inner[p];
    if (c < 0 || c >= n) continue;
    for (int q = outer[c]; q < outer[c + 1]; ++q)
      if (inner[q] == ri) {
        saved.entries.emplace_back(&val[q], val[q]);
        val[q] = (c == ri) ? s : 0.0;
      }
  }
  return saved;
}

double mean_abs_diagonal(const SparseMatrix& A) {
  double sum = 0.0;
  for (int c = 0; c < A.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(A, c); it; ++it)
      if (it.row() == c) sum += std::abs(it.value());
  return sum / static_cast<double>(A.rows());
}

/// max_k |(A p)_k| / max_k (|A||p|)_k over all rows, and the same ratio for row r.
std::pair<double, double> residuals(const SparseMatrix& A, const std::vector<double>& p, std::size_t r) {
  std::vector<double> ap(p.size(), 0.0), abs_ap(p.size(), 0.0);
  for (int c = 0; c < A.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(A, c); it; ++it) {
      ap[static_cast<std::size_t>(it.row())] += it.value() * p[static_cast<std::size_t>(c)];
      abs_ap[static_cast<std::size_t>(it.row())] +=
          std::abs(it.value()) * std::abs(p[static_cast<std::size_t>(c)]);
    }
  double num = 0.0, den = 0.0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    num = std::max(num, std::abs(ap[k]));
    den = std::max(den, abs_ap[k]);
  }
  const double dropped = abs_ap[r] > 0 ? std::abs(ap[r]) / den : 0.0;
  return {den > 0 ? num / den : 0.0, dropped};
}

void normalize(std::vector<double>& p, double area) {
  double s = 0.0;
  for (double v : p) s += v;
  s *= area;
  if (!(std::isfinite(s) && s > 0.0))
    throw SolveBreakdown("the FPK solution has no positive mass (the solve broke down; check the model and grid)");
  for (double& v : p) v /= s;
}

/// Direct solve: LU of A with equation r replaced by the normalisation row.
/// UMFPACK's two phases on A, each announced through `log` before it starts (a large grid takes
/// minutes inside them without a word) and timed.
void factorize_logged(DirectSolverCache::Impl& lu, const SparseMatrix& A, const Grid& g,
                      const std::function<void(const std::string&)>& log) {
  const std::string cells = std::to_string(g.x.n) + "x" + std::to_string(g.y.n) + " cells";
  auto t0 = Clock::now();
  double symbolic = 0.0;
  if (!lu.matches(A)) {
    if (log) log("factorising " + cells + " (symbolic)...");
    lu.analyze(A);
    symbolic = seconds_since(t0);
    t0 = Clock::now();
  }
  if (log) log("factorising " + cells + " (numeric)...");
  lu.factorize(A);
  if (log)
    log("factorised in " + vehs::detail::format_number(symbolic, 3) + " s (symbolic) + " +
        vehs::detail::format_number(seconds_since(t0), 3) + " s (numeric), " +
        vehs::detail::format_number(lu.factor_megabytes(), 3) + " MB of factors");
}

std::vector<double> solve_direct(const FpkModel& model, SparseMatrix& A, const Grid& g,
                                 DirectSolverCache* cache, Ordering ordering, SolveSummary& sum,
                                 const std::function<void(const std::string&)>& log,
                                 SparseMatrix* high = nullptr, int correction_steps = 0) {
  DirectSolverCache local;
  DirectSolverCache::Impl& lu = detail::SolverAccess::of(cache ? *cache : local);
  if (!cache) lu.set_ordering(ordering);  // a cache keeps the ordering it was analysed with
  const double s = mean_abs_diagonal(A);
  std::size_t r = guess_maximum(model, g);
  const std::size_t n = g.size();
  std::vector<double> rhs(n, 0.0), p(n, 0.0);
  for (int attempt = 1; attempt <= 2; ++attempt) {
    SavedRow saved = set_normalization_row(A, r, s);
    rhs.assign(n, 0.0);
    rhs[r] = s;
    factorize_logged(lu, A, g, log);
    lu.solve(A, rhs.data(), p.data());
    if (high && correction_steps > 0) {
      // defect correction towards the high-order operator: p ← p + A⁻¹(b − H p)
      SavedRow saved_h = set_normalization_row(*high, r, s);
      std::vector<double> res(n), delta(n);
      for (int step = 0; step < correction_steps; ++step) {
        res = rhs;
        const int* outer = high->outerIndexPtr();
        const int* inner = high->innerIndexPtr();
        const double* val = high->valuePtr();
        for (std::size_t c = 0; c < n; ++c)
          for (int q = outer[c]; q < outer[c + 1]; ++q) res[static_cast<std::size_t>(inner[q])] -= val[q] * p[c];
        lu.solve(A, res.data(), delta.data());
        for (std::size_t k = 0; k < n; ++k) p[k] += delta[k];
      }
      saved_h.restore();
      sum.iterations = correction_steps;
    }
    saved.restore();
    sum.normalization_row = r;
    sum.normalization_attempts = attempt;
    sum.factor_nonzeros = lu.factor_nonzeros();
    sum.factor_megabytes = lu.factor_megabytes();
    for (double v : p)
      require(std::isfinite(v), model.where() + ": the direct FPK solve produced a non-finite "
                                                "density (the system is numerically singular)");
    const auto mx = std::max_element(p.begin(), p.end());
    if (p[r] >= 0.01 * *mx) break;
    r = static_cast<std::size_t>(mx - p.begin());  // the guess was poor: fix the true maximum
  }
  lu.release_numeric();
  return p;
}

std::vector<double> solve_sor(const SparseMatrix& A, const Grid& g, const SorOptions& o,
                              SolveSummary& sum) {
  const Eigen::SparseMatrix<double, Eigen::RowMajor, int> R = A;
  const std::size_t n = g.size();
  const double area = g.cell_area();
  const double total_area = area * static_cast<double>(n);
  std::vector<double> p(n, 1.0 / total_area);
  std::vector<double> diag(n, 0.0);
  for (int k = 0; k < R.outerSize(); ++k)
    for (decltype(R)::InnerIterator it(R, k); it; ++it)
      if (it.col() == k) diag[static_cast<std::size_t>(k)] = it.value();
  for (std::size_t k = 0; k < n; ++k)
    require(diag[k] != 0.0, "sor: zero diagonal in the FPK matrix (cell " + std::to_string(k) + ")");
  const int* outer = R.outerIndexPtr();
  const int* inner = R.innerIndexPtr();
  const double* val = R.valuePtr();
  sum.converged = false;
  vehs::detail::ProgressCounter progress(o.progress, "fpk sor", o.max_iterations);
  long it = 0;
  for (it = 1; it <= o.max_iterations; ++it) {
    if (it % 100 == 0) progress.advance(100);
    double change = 0.0, pmax = 0.0;
    // the paper's order: p = (p_11, …, p_m1, p_12, …): x index fastest
    for (int j = 0; j < g.y.n; ++j)
      for (int i = 0; i < g.x.n; ++i) {
        const std::size_t k = g.index(i, j);
        double r = 0.0;
        for (int q = outer[k]; q < outer[k + 1]; ++q) r += val[q] * p[static_cast<std::size_t>(inner[q])];
        double v = p[k] - o.alpha * r / diag[k];
        if (v < 0.0) v = 0.0;  // the paper clips negative densities
        change = std::max(change, std::abs(v - p[k]));
        p[k] = v;
        pmax = std::max(pmax, v);
      }
    require(std::isfinite(change) && pmax > 0.0,
            "sor: the iteration diverged or collapsed to zero after " + std::to_string(it) +
                " sweeps (try a smaller sor.alpha or the direct solver)");
    if (it % o.normalize_every == 0) normalize(p, area);
    if (change < o.tolerance * pmax) {
      sum.converged = true;
      break;
    }
  }
  sum.iterations = std::min(it, o.max_iterations);
  return p;
}

std::vector<double> solve_bicgstab(const FpkModel& model, SparseMatrix& A, const Grid& g,
                                   const IterativeOptions& o, SolveSummary& sum) {
  const double s = mean_abs_diagonal(A);
  const std::size_t r = guess_maximum(model, g);
  SavedRow saved = set_normalization_row(A, r, s);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(g.size()));
  rhs[static_cast<Eigen::Index>(r)] = s;
  Eigen::BiCGSTAB<SparseMatrix, Eigen::IncompleteLUT<double, int>> solver;
  solver.preconditioner().setDroptol(o.drop_tolerance);
  solver.preconditioner().setFillfactor(o.fill_factor);
  solver.setTolerance(o.tolerance);
  solver.setMaxIterations(o.max_iterations);
  solver.compute(A);
  require(solver.info() == Eigen::Success, "bicgstab: the ILUT preconditioner failed");
  Eigen::VectorXd x = solver.solve(rhs);
  saved.restore();
  sum.iterations = static_cast<long>(solver.iterations());
  sum.converged = solver.info() == Eigen::Success;
  sum.normalization_row = r;
  std::vector<double> p(x.data(), x.data() + x.size());
  for (double v : p)
    require(std::isfinite(v), "bicgstab: the iteration broke down (non-finite density); "
                              "use the direct solver");
  return p;
}

}  // namespace

double estimated_solve_bytes(std::size_t cells, const SolveOptions& options) {
  const double n = static_cast<double>(cells);
  if (options.solver == Solver::Sor) return 300.0 * n + 2e7;
  return n * (680.0 + 27.5 * std::log2(std::max(n, 2.0))) + 2e7;
}

double estimated_solve_seconds(std::size_t cells, const SolveOptions& options) {
  if (options.solver != Solver::Direct) return 0.0;
  return 1.1 * std::pow(static_cast<double>(cells) / 160000.0, 1.5);
}

StationaryResult solve_stationary(const FpkModel& model, const Grid& grid, const SolveOptions& options,
                                  DirectSolverCache* reuse) {
  if (auto why = options.invalid_reason(); !why.empty()) throw Error(why);
  const double need = estimated_solve_bytes(grid.size(), options);
  const double limit = vehs::detail::default_memory_limit(options.memory_limit);
  if (need > limit)
    throw Error("fpk: " + std::to_string(grid.x.n) + "x" + std::to_string(grid.y.n) + " cells need about " +
                vehs::detail::format_number(need / 1e9, 3) + " GB of memory (limit " +
                vehs::detail::format_number(limit / 1e9, 3) + " GB): use fewer cells");
  StationaryResult res;
  res.grid = grid;
  SolveSummary& sum = res.summary;
  sum.solver = enum_to_string(kSolverNames, options.solver);
  sum.scheme = enum_to_string(kSchemeNames, options.scheme);
  auto t0 = Clock::now();
  SparseMatrix A = assemble_operator(model, grid, options.scheme);
  sum.assemble_seconds = seconds_since(t0);
  sum.nonzeros = static_cast<std::size_t>(A.nonZeros());
  t0 = Clock::now();
  switch (options.solver) {
    case Solver::Direct:
      if (options.scheme == Scheme::Flux && options.correction_steps > 0) {
        SparseMatrix low = assemble_operator(model, grid, Scheme::Flux2);
        res.density = solve_direct(model, low, grid, reuse, options.ordering, sum, options.log, &A,
                                   options.correction_steps);
      } else {
        res.density = solve_direct(model, A, grid, reuse, options.ordering, sum, options.log);
      }
      break;
    case Solver::Sor: res.density = solve_sor(A, grid, options.sor, sum); break;
    case Solver::Bicgstab: res.density = solve_bicgstab(model, A, grid, options.iterative, sum); break;
  }
  normalize(res.density, grid.cell_area());
  sum.solve_seconds = seconds_since(t0);
  const auto [all, dropped] = residuals(A, res.density, sum.normalization_row);
  sum.residual = all;
  sum.dropped_equation_residual = options.solver == Solver::Sor ? all : dropped;
  double neg = 0.0, pmin = 0.0, pmax = 0.0;
  for (double v : res.density) {
    neg += std::min(v, 0.0);
    pmin = std::min(pmin, v);
    pmax = std::max(pmax, v);
  }
  sum.negative_mass = neg * grid.cell_area();
  sum.min_density_ratio = pmax > 0 ? pmin / pmax : 0.0;
  analyse_density(model, res);
  return res;
}

}  // namespace vehs::fpk

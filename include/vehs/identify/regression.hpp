#pragma once
// Least squares from sufficient statistics, and sparse regression (SSR, STLSQ) with model
// selection by blocked cross-validation or an information criterion.
//
// Every estimator of vehs::identify minimises a quadratic contrast
//     L(c) = c0 − 2 bᵀc + cᵀ G c
// whose statistics (G, b, c0, n) are sums over samples, kept per cross-validation fold so that
// the statistics of a training set are "total − fold" and the held-out contrast of any
// coefficient vector is computed without touching the data again. For ordinary least squares
// G = Σ φφᵀ, b = Σ φ·target, c0 = Σ target²; the corrected drift estimators add
// deterministic corrections to b and G (identify.hpp), and the diffusion fit adds weights.
//
// Solving: the sub-matrix of G on a support is column-equilibrated (scaled to unit diagonal)
// and factorised by LDLᵀ; its condition number (ratio of extreme eigenvalues of the
// equilibrated matrix) is reported, and conventions::max_gram_condition is the limit above which
// a dictionary is reported as ill-conditioned instead of being fitted.
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "vehs/core/enum_names.hpp"

namespace vehs::identify {

struct QuadraticStats {
  Eigen::MatrixXd G;  ///< symmetric (both triangles filled)
  Eigen::VectorXd b;
  double c0 = 0.0;
  double n = 0.0;  ///< number of samples summed

  QuadraticStats() = default;
  explicit QuadraticStats(int k) : G(Eigen::MatrixXd::Zero(k, k)), b(Eigen::VectorXd::Zero(k)) {}
  int size() const { return static_cast<int>(b.size()); }
  QuadraticStats& operator+=(const QuadraticStats& o);
  QuadraticStats& operator-=(const QuadraticStats& o);
  /// L(c) for coefficients `coef` on the terms `support` (all other coefficients zero).
  double loss(const std::vector<int>& support, const Eigen::VectorXd& coef) const;
};

/// A least-squares fit restricted to a support (indices into the dictionary, increasing).
struct SupportFit {
  std::vector<int> support;
  Eigen::VectorXd coef;      ///< on the support
  Eigen::VectorXd t_ratio;   ///< |coef| / sqrt((G_SS⁻¹)_jj): scale-free size (naive scale)
  double loss = 0.0;         ///< minimised contrast on the data it was fitted to
  double condition = 1.0;    ///< of the equilibrated G_SS
};

/// Minimises L on `support`. Never throws for ill-conditioning (see `condition`).
SupportFit fit_support(const QuadraticStats& s, const std::vector<int>& support);

/// 0, 1, …, n − 1: the support of a whole dictionary of n terms.
std::vector<int> full_support(int n);
/// A fit's coefficients over the whole dictionary of K terms (0 off the support; all 0 when the
/// fit failed, i.e. its condition is not finite).
Eigen::VectorXd full_coefficients(const SupportFit& fit, int K);

/// Condition number of the equilibrated G restricted to `support`; when `weakest` is given,
/// it receives the eigenvector (on the support, equilibrated scale) of the smallest eigenvalue.
double equilibrated_condition(const Eigen::MatrixXd& G, const std::vector<int>& support,
                              Eigen::VectorXd* weakest = nullptr);

/// Throws vehs::Error("<what> is ill-conditioned ... nearly collinear terms a, b, c") when
/// the equilibrated condition number exceeds conventions::max_gram_condition. Returns it.
double require_well_conditioned(const Eigen::MatrixXd& G, const std::vector<int>& support,
                                const std::vector<std::string>& names, const std::string& what);

enum class Sparsity { Ssr, Stlsq, None };
inline constexpr EnumNames<Sparsity, 3> kSparsityNames{
    {{Sparsity::Ssr, "ssr"}, {Sparsity::Stlsq, "stlsq"}, {Sparsity::None, "none"}}};

/// Which term SSR removes at each step: the smallest t-ratio |c|/se (scale-free: the answer does
/// not change when a column is rescaled) or, as in the seed paper, the smallest |c|.
enum class SsrRule { TRatio, AbsCoef };
inline constexpr EnumNames<SsrRule, 2> kSsrRuleNames{
    {{SsrRule::TRatio, "t_ratio"}, {SsrRule::AbsCoef, "abs_coef"}}};

/// How the SSR step is chosen: the Bayesian information criterion (default), blocked CV with the
/// one-standard-error rule on paired fold differences, or the CV minimum.
///
/// Why BIC by default: with a fixed training fraction, cross-validation (like AIC) keeps a
/// spurious term with a probability that does not vanish as the data grow (Shao, JASA 1993),
/// and a dictionary of 14 terms offers many chances; BIC's log(n) penalty is selection-consistent.
/// It is evaluated as n·log(L/n)/φ + p·log(n), where φ is the long-run variance factor of the
/// residuals (1 for white residuals, 1.5 for ULI's MA(1) residuals with ρ₁ = 1/4), measured on
/// the data, so that the likelihood scale is right for correlated residuals. The CV figures of
/// every step are computed and reported either way.
enum class Criterion { Bic, Cv1se, CvMin };
inline constexpr EnumNames<Criterion, 3> kCriterionNames{
    {{Criterion::Bic, "bic"}, {Criterion::Cv1se, "cv_1se"}, {Criterion::CvMin, "cv_min"}}};

/// Stepwise sparse regression (Boninsegna et al. 2018): from `initial`, repeatedly drop one
/// term not in `keep` (the smallest by `rule`) and refit, until only kept terms remain.
/// Returns the fits, the first being the full support.
std::vector<SupportFit> ssr_path(const QuadraticStats& s, const std::vector<int>& initial,
                                 const std::vector<bool>& keep, SsrRule rule);

/// Sequentially thresholded least squares (Brunton et al. 2016): zero every coefficient with
/// |c| < threshold (terms in `keep` excepted), refit, repeat until nothing changes.
/// Returns the fits of each iteration (the last is the result).
std::vector<SupportFit> stlsq_path(const QuadraticStats& s, const std::vector<int>& initial,
                                   const std::vector<bool>& keep, double threshold);

/// The selection along a path, with everything a user needs to see it.
struct SelectionResult {
  std::vector<SupportFit> path;   ///< fits on all data
  std::vector<double> cv_loss;    ///< held-out contrast summed over folds, per step (SSR)
  std::vector<double> cv_diff;    ///< cv_loss − min cv_loss (paired over folds)
  std::vector<double> cv_diff_se; ///< standard error of cv_diff from the spread over folds
  std::vector<double> bic;        ///< n·log(L/n)/φ + p·log(n) on all data
  int min_step = 0;               ///< step with the smallest CV loss
  int chosen = 0;                 ///< selected step
  std::string rule;               ///< how `chosen` was picked (one line)
};

/// How select_sparse walks the path and picks the step.
struct SelectionOptions {
  Sparsity sparsity = Sparsity::Ssr;
  SsrRule rule = SsrRule::TRatio;
  Criterion criterion = Criterion::Bic;
  double stlsq_threshold = 0.05;   ///< |coef| threshold of STLSQ (coefficient units)
  double variance_factor = 1.0;    ///< φ of the BIC (see Criterion)
  std::string invalid_reason() const;
};

/// Runs the sparse regression on the total statistics and picks the step. `folds` are the
/// per-fold statistics whose sum is the total (blocked CV: the training set of fold f is
/// total − fold f, its SSR path is recomputed, and each step's coefficients are scored on f).
SelectionResult select_sparse(const std::vector<QuadraticStats>& folds, const std::vector<int>& initial,
                              const std::vector<bool>& keep, const SelectionOptions& options);

}  // namespace vehs::identify

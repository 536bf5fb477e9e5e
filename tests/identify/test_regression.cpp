// Least squares from sufficient statistics, SSR/STLSQ paths and selection, on regression
// problems with known solutions (ensmallen-style fixtures): the data are generated here with
// coefficients the code under test never sees.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "vehs/core/error.hpp"
#include "vehs/identify/regression.hpp"
#include "stat_bounds.hpp"

using namespace vehs::identify;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

/// y = X β + σ ε over n rows, accumulated into `folds` contiguous blocks.
std::vector<QuadraticStats> regression_problem(const VectorXd& beta, double sigma, int n, int folds,
                                               unsigned seed, double collinear = 0.0) {
  const int K = static_cast<int>(beta.size());
  std::mt19937_64 gen(vehs_test::seed(seed));
  std::normal_distribution<double> N01;
  std::vector<QuadraticStats> out(static_cast<std::size_t>(folds), QuadraticStats(K));
  for (int i = 0; i < n; ++i) {
    VectorXd x(K);
    for (int k = 0; k < K; ++k) x[k] = N01(gen) + 0.3 * k;
    if (collinear != 0.0 && K >= 2) x[K - 1] = collinear * x[0];
    const double y = x.dot(beta) + sigma * N01(gen);
    QuadraticStats& s = out[static_cast<std::size_t>(i * folds / n)];
    s.G += x * x.transpose();
    s.b += x * y;
    s.c0 += y * y;
    s.n += 1;
  }
  return out;
}

QuadraticStats total(const std::vector<QuadraticStats>& f) {
  QuadraticStats t;
  for (const auto& s : f) t += s;
  return t;
}

}  // namespace

TEST_CASE("least squares from Gram statistics recovers exact coefficients", "[identify][regression]") {
  VectorXd beta(4);
  beta << 1.5, -2.0, 0.25, 3.0;
  const auto s = total(regression_problem(beta, 0.0, 200, 1, 1));
  const SupportFit f = fit_support(s, {0, 1, 2, 3});
  for (int k = 0; k < 4; ++k) CHECK(f.coef[k] == Approx(beta[k]).epsilon(1e-10));
  CHECK(f.loss == Approx(0.0).margin(1e-8 * s.c0));
  CHECK(f.condition >= 1.0);
  // a sub-support solves the restricted normal equations
  const SupportFit g = fit_support(s, {0, 3});
  CHECK(g.coef.size() == 2);
  CHECK(g.loss > 0.0);
  // the empty model
  CHECK(fit_support(s, {}).loss == Approx(s.c0));
}

TEST_CASE("column scaling does not change the SSR path with the t-ratio rule", "[identify][regression]") {
  VectorXd beta(5);
  beta << 1.0, 0.0, -0.5, 0.0, 0.8;
  auto folds = regression_problem(beta, 1.0, 5000, 5, 2);
  // Column 4 (a true term, coefficient 0.8) in other units (×10⁷): its coefficient becomes 8e-8.
  // The zero terms' estimates are N(0, 0.014²) (n = 5000), so under the |coef| rule the rescaled
  // term goes first unless a zero term lands within 8e-8: probability 2·2·φ(0)·8e-8/0.014 = 9e-6
  // (with ×1000 it was 9 %: 11 failures in 100 seed shifts). The t-ratio path is certain: the
  // true terms have t > 35, the zero ones |t| ~ |N(0, 1)|.
  auto scaled = folds;
  for (auto& s : scaled) {
    s.G.row(4) *= 1e7;
    s.G.col(4) *= 1e7;
    s.b[4] *= 1e7;
  }
  const std::vector<bool> keep(5, false);
  const auto a = ssr_path(total(folds), {0, 1, 2, 3, 4}, keep, SsrRule::TRatio);
  const auto b = ssr_path(total(scaled), {0, 1, 2, 3, 4}, keep, SsrRule::TRatio);
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) CHECK(a[i].support == b[i].support);
  CHECK(a[2].support == std::vector<int>{0, 2, 4});  // the zero terms 1 and 3 go first
  // the |coef| rule of the paper is scale-dependent: the rescaled true term goes first
  const auto c = ssr_path(total(scaled), {0, 1, 2, 3, 4}, keep, SsrRule::AbsCoef);
  CHECK(c[1].support == std::vector<int>{0, 1, 2, 3});
}

TEST_CASE("SSR with BIC and with one-SE cross-validation select the true support", "[identify][regression]") {
  VectorXd beta(8);
  beta << 0.0, 0.5, 0.0, -0.3, 0.0, 0.0, 0.2, 0.0;
  int bic_hits = 0, cv_hits = 0;
  const int trials = 20;
  for (int t = 0; t < trials; ++t) {
    const auto folds = regression_problem(beta, 1.0, 20000, 10, 100 + static_cast<unsigned>(t));
    const std::vector<bool> keep(8, false);
    const std::vector<int> all{0, 1, 2, 3, 4, 5, 6, 7};
    const auto bic = select_sparse(folds, all, keep, {Sparsity::Ssr, SsrRule::TRatio, Criterion::Bic, 0.0});
    const auto cv = select_sparse(folds, all, keep, {Sparsity::Ssr, SsrRule::TRatio, Criterion::Cv1se, 0.0});
    const std::vector<int> truth{1, 3, 6};
    bic_hits += bic.path[static_cast<std::size_t>(bic.chosen)].support == truth;
    cv_hits += cv.path[static_cast<std::size_t>(cv.chosen)].support == truth;
    vehs_test::tally("BIC exact", bic.path[static_cast<std::size_t>(bic.chosen)].support == truth);
    vehs_test::tally("CV one-SE exact", cv.path[static_cast<std::size_t>(cv.chosen)].support == truth);
    CHECK(bic.cv_loss.size() == bic.path.size());
    CHECK(bic.cv_diff[static_cast<std::size_t>(bic.min_step)] == Approx(0.0));
  }
  INFO("BIC exact in " << bic_hits << "/" << trials << ", CV one-SE in " << cv_hits << "/" << trials);
  // BIC keeps each of the 5 zero terms with probability ≈ P(χ²₁ > log n) = 0.17 % (n = 20000):
  // a trial misses with q ≈ 0.85 % (measured over 100 seed shifts × 20 trials: 0.99 exact). With
  // q = 1 %, P(Bin(20, 0.99) < 17) = 4.3e-5 (the former 18: 1.0e-3). CV with the one-SE rule:
  // exact in 94 % of the same 2000 trials; P(Bin(20, 0.90) < 10) = 7e-7 even at a 90 % rate.
  CHECK(bic_hits >= vehs_test::binomial_floor(trials, 0.99, 5e-5));
  CHECK(vehs_test::binomial_floor(trials, 0.99, 5e-5) == 17);
  CHECK(cv_hits >= 10);
}

TEST_CASE("kept terms survive SSR and STLSQ", "[identify][regression]") {
  VectorXd beta(4);
  beta << 2.0, 0.0, 0.0, 1.0;
  const auto folds = regression_problem(beta, 0.5, 4000, 4, 7);
  std::vector<bool> keep(4, false);
  keep[2] = true;
  const auto path = ssr_path(total(folds), {0, 1, 2, 3}, keep, SsrRule::TRatio);
  CHECK(path.back().support == std::vector<int>{2});
  const auto st = stlsq_path(total(folds), {0, 1, 2, 3}, keep, 0.5);
  CHECK(st.back().support == std::vector<int>{0, 2, 3});
  const auto sel = select_sparse(folds, {0, 1, 2, 3}, keep, {Sparsity::Ssr, SsrRule::TRatio, Criterion::Bic, 0.0});
  const auto& chosen = sel.path[static_cast<std::size_t>(sel.chosen)].support;
  // the kept (zero) term 2 and the true terms 0 and 3 (t > 100) are chosen; the zero term 1 is
  // BIC's to judge (kept with P(χ²₁ > log 4000) = 0.4 %: an exact {0, 2, 3} would fail that often)
  for (int t : {0, 2, 3}) CHECK(std::count(chosen.begin(), chosen.end(), t) == 1);
}

TEST_CASE("an ill-conditioned dictionary is reported with the collinear terms", "[identify][regression]") {
  VectorXd beta(4);
  beta << 1.0, 1.0, 1.0, 0.0;
  const auto s = total(regression_problem(beta, 1.0, 1000, 1, 3, 2.0));  // column 3 = 2 × column 0
  const std::vector<std::string> names{"a", "b", "c", "d"};
  try {
    require_well_conditioned(s.G, {0, 1, 2, 3}, names, "the test dictionary");
    FAIL("no error for collinear columns");
  } catch (const vehs::Error& e) {
    const std::string what = e.what();
    INFO(what);
    CHECK(what.find("ill-conditioned") != std::string::npos);
    CHECK(what.find("a") != std::string::npos);
    CHECK(what.find("d") != std::string::npos);
    CHECK(what.find(", b") == std::string::npos);
  }
  CHECK(require_well_conditioned(s.G, {0, 1, 2}, names, "ok") < 1e6);
}

TEST_CASE("BIC off the path: a true term dropped first among collinear ones is found again",
          "[identify][regression]") {
  // y = u − 0.5 u³ + 0.2 ε on u ~ U(−1, 1), library u, u³, u⁵, u⁷, u⁹ (as x³ … x⁹ over a weakly
  // nonlinear range: a second outside tester's Duffing records lost x³ to x⁵, x⁷ this way). The
  // t-ratio path drops u³ first and never returns: its BIC choice is {u, u⁵, u⁷} (BIC −64551.8)
  // while {u, u³} has −64558.3. Deterministic (fixed generator).
  std::mt19937_64 g(3);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  std::normal_distribution<double> N;
  const int K = 5, n = 20000;
  std::vector<QuadraticStats> folds(5, QuadraticStats(K));
  for (int i = 0; i < n; ++i) {
    const double u = U(g);
    VectorXd x(K);
    x << u, u * u * u, std::pow(u, 5), std::pow(u, 7), std::pow(u, 9);
    const double y = u - 0.5 * u * u * u + 0.2 * N(g);
    QuadraticStats& s = folds[static_cast<std::size_t>(i * 5 / n)];
    s.G += x * x.transpose();
    s.b += x * y;
    s.c0 += y * y;
    s.n += 1;
  }
  const std::vector<bool> keep(K, false);
  const auto r = select_sparse(folds, {0, 1, 2, 3, 4}, keep, {Sparsity::Ssr, SsrRule::TRatio, Criterion::Bic, 0.0});
  const std::vector<int> truth{0, 1};
  // the backward path itself never holds the truth (it is the appended last step)
  for (std::size_t s = 0; s + 1 < r.path.size(); ++s) CHECK(r.path[s].support != truth);
  CHECK(r.chosen == static_cast<int>(r.path.size()) - 1);
  CHECK(r.path[static_cast<std::size_t>(r.chosen)].support == truth);
  CHECK(r.bic[static_cast<std::size_t>(r.chosen)] < r.bic[2]);
  CHECK_THAT(r.rule, Catch::Contains("off the path"));
}

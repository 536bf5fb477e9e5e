// Calibration of the paired tests on problems with known answers: Gaussian unit differences
// with and without a common (parameter) shift, many replications, rejection rates within
// binomial error bars of the nominal level.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "vehs/diagnose/hypothesis.hpp"
#include "stat_bounds.hpp"

using namespace vehs::diagnose;

namespace {
// The rejection count of n independent replications at level a is Bin(n, a) when the test is
// exact: it must lie in the exact binomial band of probability 1 − p (each check of a test case
// with k of them gets p = 1e-4/k; the former 3-sigma band failed with 2.7e-3 per check).
bool rate_ok(int rejections, int n, double a, int k) {
  vehs_test::tally("rejection rate at " + std::to_string(a), (rejections - n * a) / std::sqrt(n * a * (1 - a)));
  return vehs_test::binomial_within(rejections, n, a, vehs_test::kFalseFailure / k);
}
Eigen::MatrixXd correlated(int U, int p, std::mt19937_64& rng, double shift = 0.0) {
  std::normal_distribution<double> N;
  Eigen::MatrixXd L = Eigen::MatrixXd::Identity(p, p);
  for (int i = 1; i < p; ++i) L(i, i - 1) = 0.8;  // strongly correlated columns
  Eigen::MatrixXd D(U, p);
  for (int j = 0; j < U; ++j) {
    Eigen::VectorXd z(p);
    for (int k = 0; k < p; ++k) z[k] = N(rng);
    D.row(j) = (L * z).transpose();
    D(j, 0) += shift;
  }
  return D;
}
}  // namespace

TEST_CASE("paired Hotelling test: nominal size under the null, power against a shift", "[hypothesis]") {
  // Hotelling's T² is exact for Gaussian units (F reference): 6 rate checks and one power check.
  // Over 23 seed shifts the 69 counts per level have z sd 1.04 (5 %) and 1.09 (1 %): binomial.
  std::mt19937_64 rng(vehs_test::seed(7));
  const int n = 2000;
  for (int p : {1, 3, 8}) {
    int rej05 = 0, rej01 = 0;
    for (int i = 0; i < n; ++i) {
      const TestResult r = hotelling_zero_mean(correlated(40, p, rng));
      REQUIRE(r.available);
      rej05 += r.p_value < 0.05;
      rej01 += r.p_value < 0.01;
    }
    INFO("p = " << p << ": " << rej05 << " and " << rej01 << " rejections of " << n);
    CHECK(rate_ok(rej05, n, 0.05, 7));
    CHECK(rate_ok(rej01, n, 0.01, 7));
  }
  // power: non-centrality 40·0.64·(Σ⁻¹)₀₀ = 52 against F(3, 37) at 1 %: a miss has probability
  // < 3e-3 (normal approximation of the non-central χ²; measured power over 23 seed shifts: 0.9993),
  // so 20 misses of 200 have P(Bin(200, 3e-3) ≥ 20) < 1e-20
  int power = 0;
  for (int i = 0; i < 200; ++i) power += hotelling_zero_mean(correlated(40, 3, rng, 0.8)).p_value < 0.01;
  vehs_test::tally("power", power / 200.0);
  CHECK(power > 180);
}

TEST_CASE("a common parameter shift is calibrated when its covariance is estimated from draws", "[hypothesis]") {
  // mean of the units = common shift δ ~ N(0, Σ_δ) (what the model's parameter error does) + unit noise;
  // Σ_δ estimated from B noisy draws by the unbiased estimator used in diagnose()
  std::mt19937_64 rng(vehs_test::seed(11));
  std::normal_distribution<double> N;
  const int n = 1500, U = 40, p = 4, B = 8;
  Eigen::MatrixXd Ls = Eigen::MatrixXd::Zero(p, p);
  Ls(0, 0) = 0.6, Ls(1, 0) = 0.5, Ls(1, 1) = 0.2;  // concentrated, correlated parameter part (per-unit scale 1)
  auto draw_shift = [&]() {
    Eigen::VectorXd z(p);
    for (int k = 0; k < p; ++k) z[k] = N(rng);
    return Eigen::VectorXd(Ls * z);
  };
  int naive = 0, corrected = 0;
  for (int i = 0; i < n; ++i) {
    const Eigen::VectorXd delta = draw_shift();
    Eigen::MatrixXd D = correlated(U, p, rng);
    D.rowwise() += delta.transpose();
    Eigen::MatrixXd acc = Eigen::MatrixXd::Zero(p, p), within = acc;
    for (int b = 0; b < B; ++b) {
      Eigen::MatrixXd E = correlated(U, p, rng);
      E.rowwise() += draw_shift().transpose();
      const Eigen::VectorXd e = E.colwise().mean().transpose();
      const Eigen::MatrixXd C = E.rowwise() - e.transpose();
      acc += e * e.transpose();
      within += (C.transpose() * C) / ((U - 1.0) * U);
    }
    ExtraCovariance extra;
    extra.second_moment = acc / B;
    extra.within = within / B;
    extra.draws = B;
    extra.units = U;
    naive += hotelling_zero_mean(D).p_value < 0.05;
    const TestResult r = hotelling_zero_mean(D, 1e-9, &extra);
    REQUIRE(r.available);
    corrected += r.p_value < 0.05;
  }
  INFO("rejections at 5 %: naive " << naive << ", with the parameter covariance " << corrected << " of " << n);
  vehs_test::tally("naive rate", naive / static_cast<double>(n));
  vehs_test::tally("corrected rate", corrected / static_cast<double>(n));
  // Over 22 seed shifts: naive rate 0.620 ± sd 0.009 (the 0.15 floor is 50 sd below), corrected
  // 0.046 ± sd 0.0065 (binomial 0.0056 plus the draw-to-draw spread of the estimated Σ_δ). The
  // upper bound 0.05 + 3.99 binomial sd (one-sided 3.3e-5 at a rate of exactly 5 %) is 4.0 measured
  // sd above the measured rate (3e-5; the former 3 binomial sd: 3.2 sd, 7e-4), the floor 0.01 is
  // 5.6 sd below (1e-8).
  CHECK(naive > 3 * 0.05 * n);             // ignoring the shift is badly anti-conservative
  CHECK(corrected <= 0.05 * n + 3.99 * std::sqrt(0.05 * 0.95 * n));  // accounting for it is not
  CHECK(corrected >= 0.01 * n);            // ... and not absurdly conservative either
}

TEST_CASE("sum of t statistics: nominal size with few degrees of freedom", "[hypothesis]") {
  std::mt19937_64 rng(vehs_test::seed(3));
  std::student_t_distribution<double> T(9.0);
  const int n = 2000;
  int rej = 0;
  for (int i = 0; i < n; ++i) {
    std::vector<double> t(50), nu(50, 9.0);
    for (auto& v : t) v = T(rng);
    rej += combine_t(t, nu).p_value < 0.05;
  }
  INFO(rej << " rejections of " << n);
  // the reference is approximate for few dof, but over 22 seed shifts the count's z is
  // 0.05 ± 0.20 with sd 0.94: the size is nominal to within the resolution, so the exact binomial
  // band at 1e-4 applies
  CHECK(rate_ok(rej, n, 0.05, 1));
}

// The confirmation of suspects (include/vehs/diagnose/confirmation.hpp): what the held-out
// innovations show (src/diagnose/residual_signature.cpp) on innovation series with a known law,
// and the conclusion drawn from the verdict and the refits (src/diagnose/conclusion.cpp). The
// refits themselves run end to end in tests/tools/test_diagnose_tool.cpp (hidden dry friction:
// confirmed and recommended) and on real data in bench/diagnose_silverbox.sh.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "../../src/diagnose/comparison.hpp"
#include "../../src/diagnose/residual_signature.hpp"
#include "vehs/diagnose/confirmation.hpp"
#include "vehs/diagnose/diagnose.hpp"
#include "vehs/diagnose/suspects.hpp"

namespace {

struct Series {
  vehs::Dataset held;
  vehs::likelihood::FilterTrace trace;
};

/// 8 pieces × 2000 samples of innovations z (predicted 0, variance 1) made by `make(k, rng)`,
/// with independent N(0, 1) filtered states and an input u.
template <class Make>
Series series(std::uint64_t seed, Make make) {
  Series s;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01;
  for (int r = 0; r < 8; ++r) {
    vehs::Dataset piece;
    vehs::Record rec;
    rec.dt = 0.01;
    rec.size = 2000;
    piece.records.push_back(rec);
    for (std::size_t k = 0; k < rec.size; ++k) piece.u.push_back(n01(rng));
    for (std::size_t k = 0; k < rec.size; ++k) {
      const double y = n01(rng);
      s.trace.filtered_y.push_back(y);
      s.trace.filtered_x.push_back(n01(rng));
      s.trace.predicted_x.push_back(0.0);
      s.trace.predicted_var.push_back(1.0);
      piece.x.push_back(make(k, piece.u.values(), k > 0 ? s.trace.filtered_y[s.trace.filtered_y.size() - 2] : 0.0,
                             k > 0 ? piece.x.back() : 0.0, rng));
    }
    s.held.append(std::move(piece));
  }
  return s;
}

}  // namespace

TEST_CASE("residual signature: white innovations show nothing - tails, memory, a variance following the state, the "
          "input and a line are each named", "[diagnose][confirmation]") {
  std::normal_distribution<double> n01;
  // white N(0, 1): each of the 7 z's beyond 4.5 with probability ≤ 6.8e-6 (two-sided normal;
  // the line and input z's are Bonferroni-corrected, so smaller): ≤ 5e-5 per run in all
  const Series white = series(11, [&](std::size_t, const std::vector<double>&, double, double, std::mt19937_64& g) { return n01(g); });
  const auto w = vehs::diagnose::residual_signature(white.held, white.trace, 0.01);
  INFO(w.summary);
  CHECK(w.samples == 8 * 1999);
  CHECK(std::abs(w.lag1_z) < 4.5);
  CHECK(std::abs(w.kurtosis_z) < 4.5);
  CHECK(std::abs(w.heteroscedasticity_z) < 4.5);
  CHECK(w.input_z < 4.5);
  CHECK(w.line_z < 4.5);
  CHECK(w.summary.find("no feature") != std::string::npos);
  // each feature built in at a size whose expected z is ≥ 20 (n ≈ 16000): failure probability
  // negligible (< 1e-20 each)
  auto first_feature = [&](auto make) {
    const Series s = series(12, make);
    return vehs::diagnose::residual_signature(s.held, s.trace, 0.01).summary;
  };
  std::student_t_distribution<double> t5(5.0);  // excess kurtosis 6: z ≈ 6/√(24/16000) ≈ 150
  CHECK(first_feature([&](std::size_t, const std::vector<double>&, double, double, std::mt19937_64& g) {
          return t5(g) / std::sqrt(5.0 / 3.0);
        }).rfind("heavy-tailed", 0) == 0);
  CHECK(first_feature([&](std::size_t, const std::vector<double>&, double, double prev, std::mt19937_64& g) {
          return 0.3 * prev + std::sqrt(1 - 0.09) * n01(g);  // lag-1 0.3: z ≈ 38
        }).rfind("innovations correlated in time", 0) == 0);
  CHECK(first_feature([&](std::size_t, const std::vector<double>&, double y, double, std::mt19937_64& g) {
          return n01(g) * std::sqrt(0.2 + 0.8 * y * y);  // corr(z², ŷ²) ≈ 0.45: z ≈ 57
        }).find("innovation variance following the velocity") != std::string::npos);
  CHECK(first_feature([&](std::size_t k, const std::vector<double>& u, double, double, std::mt19937_64& g) {
          return 0.9 * n01(g) + (k >= 3 ? 0.4 * u[k - 3] : 0.0);  // corr ≈ 0.4 at lag 3: z ≈ 50
        }).rfind("innovations correlated with the input (corr 0.4", 0) == 0);
  const std::string line = first_feature([&](std::size_t k, const std::vector<double>&, double, double, std::mt19937_64& g) {
    return n01(g) + 0.3 * std::cos(2 * M_PI * 32.0 / 256.0 * double(k));  // 2π·32/(256·0.01) = 78.5 rad/time
  });
  CHECK(line.rfind("a spectral line in the innovations at 78.5", 0) == 0);
}

TEST_CASE("conclusion: confirmed effects are recommended - none confirmed at a huge significance is outside the "
          "catalogue", "[diagnose][confirmation]") {
  using namespace vehs::diagnose;
  Result r;
  r.verdict = Verdict::Inadequate;
  r.threshold = 1e-3;
  Component c{"one_step", "", TestResult{}};
  c.test.available = true;
  c.test.p_value = 1e-40;
  r.components.push_back(c);
  r.confirmation.ran = true;
  r.confirmation.residuals.summary = "heavy-tailed innovations (excess kurtosis 6.3, z 180)";
  Confirmation no;
  no.effect = "velocity_dependent_noise";
  no.reason = "not confirmed: held-out ...";
  r.confirmation.effects.push_back(no);
  detail::conclude(r, true);
  CHECK(r.recommended.empty());
  CHECK(r.outside_catalogue);
  CHECK(r.conclusion.rfind("inadequate — the misfit is outside the catalogue: one_step fails (smallest p 1e-40)", 0) == 0);
  CHECK(r.conclusion.find("no significant catalogue effect is confirmed by a refit (1 tried)") != std::string::npos);
  CHECK(r.conclusion.find("heavy-tailed innovations") != std::string::npos);
  // failing close to the threshold: not claimed to be outside the catalogue
  r.components[0].test.p_value = 1e-5;
  detail::conclude(r, true);
  CHECK_FALSE(r.outside_catalogue);
  CHECK(r.conclusion.rfind("inadequate — no catalogue effect explains the misfit", 0) == 0);
  // a confirmed effect is recommended
  Confirmation yes;
  yes.effect = "quadratic_damping";
  yes.confirmed = true;
  yes.reason = "confirmed: held-out one-step log-likelihood +670 nats (z 18)";
  r.confirmation.effects.push_back(yes);
  detail::conclude(r, true);
  REQUIRE(r.recommended.size() == 1);
  CHECK(r.recommended[0] == "quadratic_damping");
  CHECK(r.conclusion == "inadequate — add quadratic_damping (held-out one-step log-likelihood +670 nats (z 18))");
  // effects with all-data evidence come first, in their ranking (the score tests' look-alike
  // resolution is better evidence than a 30 % share); a member of an unresolved look-alike group
  // says so
  Confirmation scored;
  scored.effect = "nonlinear_damping";
  scored.confirmed = true;
  scored.all_data_z = 5.0;
  scored.reason = "confirmed: held-out one-step log-likelihood +4 nats (z 1.3), in line with ...";
  r.confirmation.effects.push_back(scored);
  ScoreSuspect group;
  group.effect = "nonlinear_damping";
  group.not_resolved_from = {"quadratic_damping"};
  r.score_suspects.ranked.push_back(group);
  detail::conclude(r, true);
  REQUIRE(r.recommended.size() == 2);
  CHECK(r.recommended[0] == "nonlinear_damping");
  CHECK(r.conclusion.find("nonlinear_damping (held-out one-step log-likelihood +4 nats (z 1.3), in line with ...) — not "
                          "resolved by these data from quadratic_damping") != std::string::npos);
  // the strongest suspect's refit failed: named and recommended, never "outside the catalogue"
  r.confirmation.effects.clear();
  r.score_suspects.ranked.clear();
  ScoreSuspect friction;
  friction.effect = "coulomb_friction";
  friction.significant = true;
  friction.z = 135.0;
  r.score_suspects.ranked.push_back(friction);
  Confirmation diverged;
  diverged.effect = "coulomb_friction";
  diverged.error = "likelihood: the filter diverged";
  diverged.reason = "not confirmed: the refit failed";
  r.confirmation.effects.push_back(diverged);
  r.components[0].test.p_value = 1e-40;
  detail::conclude(r, true);
  CHECK_FALSE(r.outside_catalogue);
  REQUIRE(r.recommended.size() == 1);
  CHECK(r.recommended[0] == "coulomb_friction");
  CHECK(r.conclusion.rfind("inadequate — suspect coulomb_friction (score test z = 135", 0) == 0);
  CHECK(r.conclusion.find("its held-out refit failed (likelihood: the filter diverged)") != std::string::npos);
  // a refit that ran and was rejected on held-out evidence leaves the verdict to the evidence
  r.confirmation.effects[0].error.clear();
  detail::conclude(r, true);
  CHECK(r.recommended.empty());
  CHECK(r.outside_catalogue);
  // an adequate model recommends nothing
  r.verdict = Verdict::Adequate;
  detail::conclude(r, true);
  CHECK(r.recommended.empty());
  CHECK(r.conclusion == "adequate");
}

// The held-out z a true effect reaches (confirmation.hpp, "decision"): an effect of all-data
// z-equivalent z_all, refitted on the first 70 % and judged by its held-out log-likelihood gain
// over 8 pieces, has held-out z about √f·z_all/2 — which is why a split alone confirms an effect
// of z_all 5 (0.27·5 = 1.4) in a minority of data sets. A Gaussian mean at δ = 5 SE on all the
// data, 2000 replications: the held-out z minus expected_heldout_z has mean ≈ +0.2 (the t law
// of 8 pieces), sd ≈ 1.3, and falls below −consistency_margin (2.5) in ≈ 1 % (a true effect
// failing the consistency check). Bounds: the mean within [−0.3, 0.7] (≥ 7 SE of the mean
// from the measured value), below −2.5 in at most 45 of 2000 (expected ≈ 21; Poisson tail
// P(≥ 46) < 1e-5): false failure ≤ 1e-4.
TEST_CASE("confirmation: a true effect's held-out z is what its all-data z predicts for the share",
          "[diagnose][confirmation]") {
  std::mt19937_64 rng(20261128);
  std::normal_distribution<double> n01;
  const std::size_t n = 20000, train = 14000;
  const double f = double(n - train) / double(n), delta = 5.0, mu = delta / std::sqrt(double(n));
  double sum = 0.0;
  int below = 0;
  const int reps = 2000;
  std::vector<double> y(n);
  for (int rep = 0; rep < reps; ++rep) {
    double all = 0.0, fit = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      y[i] = mu + n01(rng);
      all += y[i];
      if (i < train) fit += y[i];
    }
    const double z_all = all / std::sqrt(double(n)), m = fit / double(train);
    std::vector<double> gain(8, 0.0);  // log N(y; m, 1) − log N(y; 0, 1) per held-out piece
    for (std::size_t i = train; i < n; ++i) gain[(i - train) * 8 / (n - train)] += m * y[i] - 0.5 * m * m;
    const double resid = vehs::diagnose::block_z(gain) - vehs::diagnose::expected_heldout_z(z_all, f);
    sum += resid;
    below += resid < -2.5;
  }
  INFO("mean held-out z minus the prediction " << sum / reps << ", below -2.5 in " << below << " of " << reps);
  CHECK(sum / reps > -0.3);
  CHECK(sum / reps < 0.7);
  CHECK(below <= 45);
}

// A further effect is confirmed beside those kept only when its size is significant in the joint
// refit (an outside tester's per-record forcing: a hidden electrical state "confirmed beyond" it
// with coupling 0.114 ± 0.074). The size is read from the parameters that vanish without the
// effect — never the rate λ, the frequency ω or a phase.
TEST_CASE("confirmation: an effect's size in a refit is read from the parameters that vanish without it",
          "[diagnose][confirmation]") {
  using vehs::diagnose::Confirmation;
  using vehs::diagnose::effect_size_z;
  Confirmation em;
  em.effect = "electromechanical_coupling";
  em.params = {{"lambda", 5.0}, {"coupling", 0.114}};
  em.params_stderr = {{"lambda", 0.01}, {"coupling", 0.074}};
  CHECK(effect_size_z(em) == Approx(0.114 / 0.074));  // not λ's z of 500
  Confirmation forcing;
  forcing.effect = "harmonic_forcing";
  forcing.params = {{"amplitude", -0.3}, {"omega", 1.2}, {"phase", 2.0}};
  forcing.params_stderr = {{"amplitude", 0.05}, {"omega", 0.001}, {"phase", 0.01}};
  CHECK(effect_size_z(forcing) == Approx(6.0));  // |amplitude|/SE, a negative size counts
  Confirmation stop;
  stop.effect = "impact_stop";
  stop.params = {{"k_stop", 50.0}, {"gap", 1.5}};
  stop.params_stderr = {{"k_stop", 1.0}, {"gap", 0.01}};
  CHECK(std::isnan(effect_size_z(stop)));  // no size parameter: the held-out gain decides alone
  Confirmation no_se;
  no_se.effect = "coulomb_friction";
  no_se.params = {{"mu", 0.04}};
  CHECK(std::isnan(effect_size_z(no_se)));
}

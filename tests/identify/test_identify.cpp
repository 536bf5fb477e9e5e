// Identification against independent truth: data simulated from the seed paper's penta-stable
// harvester (Eq. 27) with parameters the estimator never sees, either by the paper's own scheme
// (Eq. 30 at the recorded step) or as a sensor samples a continuous process (fine internal
// steps), with and without white sensor noise. Instances are smaller than the paper's (10⁷
// samples) to keep CI fast; bench/bench_identify_calibration.cpp runs the full-size figures.
// False failures (COMMON.md, ≤ 1e-4 per test case): coefficients within z_limit(k) standard
// errors (identify_fixtures.hpp), supports with at most one spurious term (check_support), and
// every other statistical figure with its own bound below. Seed studies of all of them:
// scripts/seed-study.sh 50 build/tests/test_identify "[identify]~[app]".
#include <catch2/catch.hpp>

#include "identify_fixtures.hpp"
#include "vehs/core/parallel.hpp"
#include "vehs/core/error.hpp"
#include "vehs/io/model_file.hpp"

using namespace vehs;
using namespace vehs_test;

namespace {
const std::set<std::string> kTrueDrift{"x", "x^3", "x^5", "x^7", "x^9", "y"};
const std::set<std::string> kTrueDiffusion{"1", "x^2"};
}  // namespace

TEST_CASE("issue 2: default settings on the paper's own scheme find the six drift and two diffusion terms",
          "[identify][paper]") {
  const Model truth = paper_truth();
  const Dataset d = simulate(truth, 0.001, 1, 20, 100000, 2701);
  const identify::Result r = identify::identify(d, identify::Options{});
  INFO(r.report.drift_selection.selection.rule);
  // ρ_k of white residuals over the pilot's 2.5·10⁵ rows: sd 1/√rows = 0.002, so 0.05 is 25 sd
  // and the rule's threshold (≈ 0.125) 60 sd away: no false failure (< 1e-100)
  tally("rho_k", r.model.fit->sampling.rho_k);
  CHECK(r.model.fit->estimator == identify::Estimator::Forward);  // scheme-consistent data detected
  CHECK(std::abs(r.model.fit->sampling.rho_k) < 0.05);
  check_support(r.model, truth, 11);  // 14 + 5 library terms, 8 true
  // 8 true coefficients: 8 z-checks (false failure ≤ 1e-4)
  const Deviation dev = compare(r.model, truth);
  CHECK(dev.max_z <= z_limit(8));
  // bias checks: the diffusion's SE is 0.3 % here (0.2 % for 2D): 2 % is ≥ 6.5 SE, and the mean
  // error over 50 seeds is ≤ 0.1 % (seed study): false failure < 1e-10
  CHECK(rel_error(r.model, truth, true, "1") <= 0.02);
  CHECK(rel_error(r.model, truth, true, "x^2") <= 0.02);
  // every reported coefficient has a standard error, and the path is in the model file
  for (const auto& tc : r.model.drift) CHECK(r.model.drift_stderr.count(tc.term.name()) == 1);
  CHECK(r.report.drift_selection.selection.path.size() == 15);
  CHECK(r.model.fit->sampling.verdict == vehs::SamplingVerdict::SchemeConsistent);
}

TEST_CASE("continuous-time records: correct support, coefficients within 3 standard errors",
          "[identify][continuous]") {
  const double dt = GENERATE(0.01, 0.005, 0.001);
  CAPTURE(dt);
  const Model truth = paper_truth();
  const Dataset d = simulate(truth, dt, 20, 20, 100000, 31 + static_cast<std::uint64_t>(1e4 * dt));
  const identify::Result r = identify::identify(d, identify::Options{});
  // ρ_k of MA(1) residuals (ρ = 1/4) over the pilot's 2.5·10⁵ rows: sd ≈ 0.002, the 0.03 margin
  // is 15 sd once the O(h) shift is counted (mean over 50 seeds in the seed study: within 0.01
  // of 1/4 at every dt); the rule's threshold 0.125 is 60 sd away: no false failure (< 1e-40)
  tally("rho_k", r.model.fit->sampling.rho_k);
  CHECK(r.model.fit->estimator == identify::Estimator::Uli);
  CHECK(r.model.fit->sampling.rho_k == Approx(0.25).margin(0.03));
  check_support(r.model, truth, 11);  // 14 + 5 library terms, 8 true
  const Deviation dev = compare(r.model, truth);
  CHECK(dev.max_z <= z_limit(8));
  // Bias checks within 5 % wherever these data resolve 5 % at the z limit (SE below
  // 5 %/z_limit(8)): then |error| > 5 % needs |z| > z_limit(8), which the check above bounds; the
  // bias itself is measured over 50 seeds (seed study: every coefficient's mean error below 1 %
  // and below 0.2 of its SE). The full-size figures (10⁷ samples) are in
  // bench/bench_identify_calibration.cpp.
  for (const auto& tc : truth.drift) {
    const double se = r.model.drift_stderr.at(tc.term.name());
    if (se < 0.05 / z_limit(8) * std::abs(tc.coef)) CHECK(rel_error(r.model, truth, false, tc.term.name()) <= 0.05);
  }
  // diffusion SE ≈ 0.3 %: 5 % is ≥ 15 SE (false failure < 1e-40 with the measured bias ≤ 0.2 %)
  CHECK(rel_error(r.model, truth, true, "1") <= 0.05);
  CHECK(rel_error(r.model, truth, true, "x^2") <= 0.05);
  // the residuals of a continuous process sampled at dt are MA(1) with lag-1 correlation 1/4
  // (2·10⁶ rows: sd 0.0006; margin as for ρ_k above)
  const double lag1 = r.report.residuals.autocorrelation_at(1);
  tally("lag1", lag1);
  CHECK(lag1 == Approx(0.25).margin(0.03));
}

TEST_CASE("the paper's estimator shows its documented biases (why the default exists)", "[identify][paper]") {
  const Model truth = paper_truth();
  identify::Options paper;
  paper.estimator = identify::Estimator::Paper;
  SECTION("continuous-time records at dt = 0.001: damping about a third low, 2D low") {
    const Dataset d = simulate(truth, 0.001, 20, 20, 100000, 77);
    const auto p = identify::identify(d, paper);
    const auto u = identify::identify(d, identify::Options{});
    const double beta_paper = -p.model.drift_coef("y"), beta_uli = -u.model.drift_coef("y");
    INFO("paper beta " << beta_paper << ", default beta " << beta_uli << " +- " << u.model.drift_stderr.at("y"));
    tally("paper beta", beta_paper);
    tally("default beta z", (beta_uli - 0.1) / u.model.drift_stderr.at("y"));
    tally("paper 2D", p.model.diffusion_coef("1"));
    // The paper's β over 9 seed shifts: 0.0684 ± sd 0.0041 (a third low, as documented). The band
    // [0.045, 0.09] is ≥ 5.3 sd from that mean (≥ 4.1 sd if the sd is 30 % larger than measured:
    // 4e-5); the former upper end 0.08 was 2.8 sd away (2.5e-3 per run). The paper's 2D:
    // 0.01414 ± 0.00009, 20 sd below 0.016.
    CHECK(beta_paper < 0.9 * 0.1);
    CHECK(beta_paper > 0.45 * 0.1);
    CHECK(std::abs(beta_uli - 0.1) <= z_limit(1) * u.model.drift_stderr.at("y"));
    CHECK(p.model.diffusion_coef("1") < 0.8 * 0.02);
  }
  SECTION("the paper's own scheme: raw Kramers-Moyal diffusion halves 2Q") {
    const Dataset d = simulate(truth, 0.001, 1, 20, 100000, 78);
    const auto p = identify::identify(d, paper);
    const double q2 = p.model.diffusion_coef("x^2");
    INFO(model_to_json(p.model)["diffusion"].dump());
    tally("paper 2Q", q2);
    // the raw Kramers–Moyal 2Q over 9 seed shifts: 0.0046 ± sd 0.0007 (half the truth): 0.0075 is
    // 4.3 sd away (1e-5)
    CHECK((q2 < 0.75 * 0.01 || names(p.model.diffusion) != kTrueDiffusion));
  }
}

TEST_CASE("white sensor noise (sd 1e-3 at dt = 0.005): the noisy estimator's stride, beta within its SE, 2D within 10 %",
          "[identify][noise]") {
  const Model truth = paper_truth();
  const Dataset d = simulate(truth, 0.005, 20, 20, 100000, 4242, 1e-3);
  const identify::Result r = identify::identify(d, identify::Options{});
  auto se_of = [](const std::map<std::string, double>& se, const char* n) {
    const auto it = se.find(n);
    return it == se.end() ? NAN : it->second;
  };
  const double beta_z = (r.model.drift_coef("y") + 0.1) / se_of(r.model.drift_stderr, "y");
  tally("sensor noise sd", r.model.fit->sampling.sensor_noise_sd / 1e-3 - 1.0);
  tally("stride", r.model.fit->stride);
  tally("beta z", beta_z, r.model.drift_coef("y") / -0.1 - 1.0);
  tally("2D z", (r.model.diffusion_coef("1") - 0.02) / se_of(r.model.diffusion_stderr, "1"),
        r.model.diffusion_coef("1") / 0.02 - 1.0);
  CHECK(r.model.fit->estimator == identify::Estimator::Noisy);
  // Seed study (issue 11; scripts/seed-study.sh 100 build/tests/test_identify "white sensor noise*").
  // Before: the stride search stopped at the first noise share η_k below the goal 0.95, and η_k
  // (≈ 1 − 1e-3 at strides 1–2, sd ≈ 0.02) fell below it by its own noise: over 62 seeds the
  // stride was 1 (3 seeds: the fit broke down), 2 (2), 3 (1), 4 (4), 5 (41), 6 (11) and the test
  // failed in 11. The estimator now searches until η_k is 4 SE below the goal
  // (noisy_stride_pilot); over 100 seeds: stride 5 (81) or 6 (19), no broken fit, and
  //  * β: z mean −0.04 ± 0.10, sd 0.96, max |z| 2.45; relative error −0.27 % ± 0.44 %, sd 4.4 %
  //    (unbiased, standard errors calibrated). The former check "β within 10 %" was 2.3 sd of
  //    these data (3 of the 100 runs failed it): β is checked against its SE at z_limit(1) = 4.47,
  //    ≥ 4.0 sd even at the upper 95 % limit of the sd (1.12): ≤ 6e-5;
  //  * 2D: +0.29 % ± 0.18 %, sd 1.8 %: 10 % is 5.5 sd (< 1e-7);
  //  * the stride: the cube-root solve from the pilot at k = 8 (η ≈ 0.85 ± 0.024) gives 5.35 with
  //    sd ≈ 0.34 (error propagation): [3, 8] is ≥ 5.4 sd away (< 1e-7);
  //  * the noise sd: relative sd 0.54 %, 10 % is 18 sd; no spurious term in 100 runs.
  // Not checked (documented limits of the noisy estimator, vehs/identify/identify.hpp: x-noise in
  // the Gram matrix is neglected): the polynomial drift terms sit 0.43–0.63 SE off on average
  // (sd of z 1.08–1.12) and 2Q −3.2 % ± 0.4 % (−0.84 SE): z-checks on them at z_limit would leave
  // < 4 sd. They are printed and tallied by compare().
  CHECK(r.model.fit->stride >= 3);
  CHECK(r.model.fit->stride <= 8);
  CHECK(r.model.fit->sampling.sensor_noise_sd == Approx(1e-3).epsilon(0.1));
  compare(r.model, truth);
  CHECK(std::abs(beta_z) <= z_limit(1));
  CHECK(rel_error(r.model, truth, true, "1") <= 0.10);
  Model drift_only = truth;  // the drift's support (the diffusion's is not this test's subject)
  drift_only.diffusion = r.model.diffusion;
  check_support(r.model, drift_only, 8);
}

TEST_CASE("results do not depend on the number of threads", "[identify]") {
  const Dataset d = simulate(paper_truth(), 0.01, 20, 6, 20000, 5);
  auto run = [&](int threads) {
    set_threads(threads);
    const auto r = identify::identify(d, identify::Options{});
    std::string s = model_to_json(r.model).dump();  // coefficients, standard errors, fit
    for (const auto* sel : {&r.report.drift_selection.selection, &r.report.diffusion_selection.selection})
      for (std::size_t k = 0; k < sel->path.size(); ++k)
        s += " " + std::to_string(sel->bic[k]) + " " + std::to_string(sel->cv_loss[k]);
    return s + " " + std::to_string(r.report.residuals.rms);
  };
  const std::string one = run(1), two = run(2);
  set_threads(0);
  CHECK(one == two);
}

TEST_CASE("Coulomb friction as an effect: kept in the dictionary, mu reported with its standard error",
          "[identify][effects]") {
  Model truth = paper_truth();
  truth.drift.push_back({Term::sign_y(), -0.05});
  canonicalize(truth.drift, "truth");
  const Dataset d = simulate(truth, 0.005, 20, 20, 100000, 99);
  identify::Options o;
  o.effects.push_back(effect_from_json("coulomb_friction", "test", false));
  const auto r = identify::identify(d, o);
  INFO(model_to_json(r.model).dump());
  REQUIRE(r.report.effect_params.size() == 1);
  const double mu = r.report.effect_params[0].params.at("mu");
  const double se = r.report.effect_params[0].stderr_.at("mu");
  tally("mu", (mu - 0.05) / se, mu / 0.05 - 1);
  // 9 z-checks (mu and the 8 terms; mu is −coef of sign(y), so one family of 9 coefficients);
  // SE(mu) ≈ 0.0027: 0.02 is 7× it. The diffusion's bias with sign(y) in the drift (issue 11):
  // none beyond the generic +0.1 % (0.7 SE) of the friction-free control, and mu's −5.5 % bias
  // (−1.1 SE) from sign(v̂) is removed by the smoothed sign (tests/identify/test_bias_study.cpp).
  CHECK(std::abs(mu - 0.05) <= z_limit(9) * se);
  CHECK(se < 0.02);
  CHECK(compare(r.model, truth).max_z <= z_limit(9));
}

TEST_CASE("a recorded drive u is identified as a term", "[identify][drive]") {
  Model truth = paper_truth();
  truth.drift.push_back({Term::drive(), 0.5});
  canonicalize(truth.drift, "truth");
  sim::SimulationOptions so;
  so.dt = 0.01;
  so.substeps = 20;
  so.records = 10;
  so.samples = 100000;
  so.seed = seed(11);
  so.record_y = false;
  for (std::size_t i = 0; i < so.samples; ++i) so.drive.push_back(0.3 * std::cos(0.7 * 0.01 * static_cast<double>(i)));
  const Dataset d = sim::simulate(truth, so);
  REQUIRE(d.has_u());
  identify::Options o;
  o.drift_library.push_back(Term::drive());
  const auto r = identify::identify(d, o);
  // u's coefficient 0.5 with SE ≈ 0.01: dropping it needs a 50-SE error
  CHECK(names(r.model.drift).count("u") == 1);
  CHECK(compare(r.model, truth).max_z <= z_limit(9));  // 9 true terms
}

TEST_CASE("unusable records are rejected with the record and row named", "[identify][errors]") {
  auto record = [](Dataset& d, long long id, std::vector<double> x) {
    Record r;
    r.source = "rec.csv";
    r.id = id;
    r.first_line = d.x.size() + 2;
    r.dt = 0.01;
    r.offset = d.x.size();
    r.size = x.size();
    d.x.insert(d.x.end(), x.begin(), x.end());
    d.records.push_back(r);
  };
  std::vector<double> good(2000);
  for (std::size_t i = 0; i < good.size(); ++i) good[i] = std::sin(0.05 * static_cast<double>(i));
  auto expect = [](const Dataset& d, const std::string& text) {
    try {
      identify::identify(d, identify::Options{});
      FAIL("no error");
    } catch (const Error& e) {
      INFO(e.what());
      CHECK(std::string(e.what()).find(text) != std::string::npos);
      CHECK(std::string(e.what()).find('\n') == std::string::npos);
    }
  };
  {
    Dataset d;
    record(d, 1, good);
    auto bad = good;
    bad[700] = std::nan("");
    record(d, 2, bad);
    expect(d, "rec.csv: record traj=2");
    expect(d, "line 2702");
  }
  {
    Dataset d;
    record(d, 1, good);
    record(d, 5, std::vector<double>(500, 0.25));
    expect(d, "traj=5");
    expect(d, "constant");
  }
  {
    Dataset d;
    record(d, 3, std::vector<double>(good.begin(), good.begin() + 10));
    expect(d, "only 10 samples");
  }
  {
    identify::Options o;
    o.effects.push_back(effect_from_json("colored_noise", "test", false));
    o.effects.push_back(effect_from_json("harmonic_forcing", "test", false));
    Dataset d;
    record(d, 1, good);
    try {
      identify::identify(d, o);
      FAIL("no error");
    } catch (const Error& e) {
      CHECK(std::string(e.what()).find("cannot yet be combined") != std::string::npos);
    }
  }
}

TEST_CASE("a singular dictionary is reported, not fitted", "[identify][errors]") {
  // x jumps between -1 and +1: 1, x^2 and x^4 are the same column
  Dataset d;
  Record r;
  r.source = "square.csv";
  r.dt = 0.01;
  r.size = 5000;
  for (std::size_t i = 0; i < r.size; ++i) d.x.push_back((i / 7) % 2 ? 1.0 : -1.0);
  d.records.push_back(r);
  identify::Options o;
  o.drift_library = {Term::monomial(0), Term::monomial(2), Term::monomial(4), Term::monomial(0, 1)};
  try {
    identify::identify(d, o);
    FAIL("no error");
  } catch (const Error& e) {
    const std::string what = e.what();
    INFO(what);
    CHECK(what.find("ill-conditioned") != std::string::npos);
    CHECK(what.find("x^2") != std::string::npos);
    CHECK(what.find("x^4") != std::string::npos);
  }
}

TEST_CASE("the O(h^2) central-difference correction removes the stride bias of ULI", "[identify][continuous]") {
  // at stride 14 (h = 0.07) the uncorrected central difference biases the stiffness by ~5 %
  // (4-7 standard errors); the (h²/12)·x'''' correction brings it back within 3
  const Model truth = paper_truth();
  const Dataset d = simulate(truth, 0.005, 20, 20, 100000, 314);
  identify::Options o;
  o.estimator = identify::Estimator::Uli;
  o.stride = 14;
  const auto with = identify::identify(d, o);
  o.discretization_correction = false;
  const auto without = identify::identify(d, o);
  // The drift: support and 6 z-checks. The diffusion is not this test's subject: at h = 0.07 its
  // O(h) bias (identify.hpp) is measured over 8 seed shifts at x^2 −2.7 % ± 0.8 % (−1.6 SE) and
  // 1 +0.7 % ± 0.3 %, so a z-check of it would fail often (the former max_z ≤ 3 over all 8 terms
  // failed in 1 of 8 seed shifts).
  Model drift_only = truth;
  drift_only.diffusion = with.model.diffusion;
  check_support(with.model, drift_only, 8);
  CHECK(compare(with.model, drift_only).max_z <= z_limit(6));
  tally("x^9 error without / with", rel_error(without.model, truth, false, "x^9") / rel_error(with.model, truth, false, "x^9"));
  tally("x^5 error with", rel_error(with.model, truth, false, "x^5"));
  // The uncorrected stiffness is ~5 % off (4–7 SE) at this stride and the corrected one within
  // 1–2 SE. Over 40 seed shifts (scripts/seed-study.sh 40 build/tests/test_identify "the O(h^2)
  // central-difference correction*"): x^9's error without / with the correction ≥ 3.4 (median
  // 8.2), the corrected x^9 +0.35 % ± sd 0.52 %: a ratio below 2 needs the corrected error
  // above ≈ 2.5 %, 4 sd away (≈ 3e-5). The corrected x^5 is +0.37 % ± sd 0.75 % (z +0.46 ± sd
  // 0.93): the former check |error| < 2 % was 2.2 sd away (≈ 1.5 % false failure per run; the
  // largest of the 40 was 1.95 %), so x^5 is checked by its z above (z_limit(6)) only.
  CHECK(rel_error(without.model, truth, false, "x^9") > 2 * rel_error(with.model, truth, false, "x^9"));
}

// False failure ≤ 1e-4: four estimates within z_limit(4); the estimator check: lag 1 of the
// fit's residuals is ≈ 0.232 here (12 of its SEs of ≈ 0.0014 below 1/4) against a bar of 4 SEs,
// 0.244. A Duffing in volts (10 Hz, β 6.28, k 1000, σ 223) at 5 kHz, 20
// records × 4 s, with white sensor noise of 30 µV (0.004 % of sd(x)): about 2 % of the ULI
// acceleration's variance, under the sampling rule's 5 % floor and below its pilot's
// resolution, so the ULI fit took it for diffusion and wrote 2D at z +7.5 to +10.9 (3 seeds,
// exit 0). The final fit's residuals show it at lag 1 (1/4 − (11/12)η); noisy then refits.
TEST_CASE("white sensor noise too small for the sampling rule: the ULI residuals read it, 2D unbiased",
          "[identify][noise][residual_noise]") {
  const double w = 2.0 * M_PI * 10.0;
  const Model truth = model_from_json(
      nlohmann::json{{"drift", {{"x", -w * w}, {"x^3", -1000.0}, {"y", -6.28}}}, {"diffusion", {{"1", 223.0 * 223.0}}}},
      "Duffing in volts");
  const Dataset d = simulate(truth, 2e-4, 20, 20, 20000, 4243, 3e-5, sim::Scheme::Taylor15);
  identify::Options o;
  o.drift_library = {Term::parse("x"), Term::parse("x^3"), Term::parse("y")};
  o.diffusion_library = {Term::parse("1")};
  o.sparsity = identify::Sparsity::None;
  const identify::Result r = identify::identify(d, o);
  INFO(r.report.estimator.reason);
  REQUIRE(r.model.fit);
  CHECK(r.model.fit->estimator == identify::Estimator::Noisy);
  for (const auto& [name, value] : std::map<std::string, double>{{"x", -w * w}, {"x^3", -1000.0}, {"y", -6.28}}) {
    INFO(name << " " << r.model.drift_coef(name) << " ± " << r.model.drift_stderr.at(name));
    CHECK(std::abs(r.model.drift_coef(name) - value) / r.model.drift_stderr.at(name) < z_limit(4));
  }
  const double q = r.model.diffusion_coef("1"), se = r.model.diffusion_stderr.at("1");
  INFO("2D " << q << " ± " << se);
  CHECK(std::abs(q - 223.0 * 223.0) / se < z_limit(4));
}

TEST_CASE("the sampling rule reads lag k far above 0 as a sensor on a continuous process, whatever its noise",
          "[identify][sampling]") {
  // the lags of a rig at 40 samples per period with 1 % sensor noise on 20 000 samples: the noise
  // share 6 (ρ_2k − ρ_3k) = 0.14 is not resolved (3 SE = 0.18) and the midpoint rule at η = 0
  // said "scheme-consistent"; but ρ_k − ρ_3k = 0.078 is 7.8 SE above any explicit scheme's
  const identify::SamplingRule r = identify::sampling_rule(0.039, -0.0159, -0.0393, 20000);
  CHECK(r.verdict == SamplingVerdict::Noisy);
  CHECK(r.continuous);
  CHECK(r.noise_share == Approx(0.19).margin(0.02));  // (1/4 − 0.078)·12/11 from lag k, lag 2k agrees
  // the same lags on few rows (SE 0.02): not refuted, the midpoint rule stands
  CHECK(identify::sampling_rule(0.039, -0.0159, -0.0393, 2000).verdict == SamplingVerdict::SchemeConsistent);
  // an explicit scheme (lag k about 0) and a clean continuous process keep their verdicts
  CHECK(identify::sampling_rule(0.002, -0.001, 0.001, 2.5e5).verdict == SamplingVerdict::SchemeConsistent);
  CHECK(identify::sampling_rule(0.25, 0.0, 0.0, 2.5e5).verdict == SamplingVerdict::ContinuousTime);
  // a continuous process with little noise: continuous, not noisy
  const identify::SamplingRule small = identify::sampling_rule(0.25 - 11.0 / 12.0 * 0.02, 0.02 / 6.0, 0.0, 20000);
  CHECK(small.verdict == SamplingVerdict::ContinuousTime);
}

// The binned Kramers–Moyal estimates drawn in identify's figures (vehs/identify/binned.hpp)
// against the exact drift and diffusion of a model with a known answer: a linear oscillator with
// multiplicative noise, b2 = −k·x − β·y, a22 = d0 + d2·x², sampled as a sensor samples a
// continuous process (20 internal steps per sample). The x-bins of the drift must average −k·x,
// the v̂-bins −β·v̂ (after the Itô/Stein correction of central kinematics), the diffusion bins
// d0 + d2·x², each within Monte Carlo error.
//
// Error bars: the estimator's rows overlap in time (the binned_estimates SE treats them as
// independent), so the test takes its error from R independent replicate datasets instead: for
// each bin, the mean over replicates of (bin mean − exact value at the bin centre) and its
// standard error from their spread, a Student t with R − 1 degrees of freedom. Every checked bin
// of the three curves is one of m two-sided checks at |t| ≤ t_bound(m, R − 1): false failure
// ≤ 1e-4 per run (Bonferroni). Deterministic biases (the bin centre vs the bin's mean x: w²/12 ·
// p'/p ≈ 4e-3 σ at 2σ with 20 bins; O(h) discretisation at h = 0.01) are below a tenth of the
// threshold's size here.
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "identify/identify_fixtures.hpp"
#include "vehs/identify/binned.hpp"

namespace {

struct Check {
  const char* curve;
  std::function<const vehs::identify::BinnedCurve&(const vehs::identify::BinnedEstimates&)> of;
  std::function<double(double)> exact;
};

}  // namespace

TEST_CASE("binned Kramers-Moyal estimates match the exact drift and diffusion of a linear oscillator",
          "[identify][binned]") {
  const double k = 1.0, beta = 0.5, d0 = 0.2, d2 = 0.1;
  const vehs::Model truth = vehs::model_from_json(
      nlohmann::json{{"drift", {{"x", -k}, {"y", -beta}}}, {"diffusion", {{"1", d0}, {"x^2", d2}}}}, "truth");
  constexpr int kReplicates = 24, kBins = 20;
  constexpr double kMinRows = 2000.0;  // bins of every replicate with at least this many rows
  const std::vector<Check> checks{
      {"drift vs x", [](const auto& b) -> const auto& { return b.drift_x; }, [&](double x) { return -k * x; }},
      {"drift vs v", [](const auto& b) -> const auto& { return b.drift_v; }, [&](double v) { return -beta * v; }},
      {"diffusion vs x", [](const auto& b) -> const auto& { return b.diffusion; }, [&](double x) { return d0 + d2 * x * x; }}};
  // deviation sums per (curve, bin) over the replicates
  std::vector<std::vector<double>> sum(checks.size(), std::vector<double>(kBins, 0.0)), sum2 = sum;
  std::vector<std::vector<bool>> usable(checks.size(), std::vector<bool>(kBins, true));
  for (int r = 0; r < kReplicates; ++r) {
    const vehs::Dataset d = vehs_test::simulate(truth, 0.01, 20, 1, 200000, 4100 + static_cast<std::uint64_t>(r));
    const vehs::identify::BinnedEstimates be = vehs::identify::binned_estimates(d, truth, kBins);
    for (std::size_t c = 0; c < checks.size(); ++c) {
      const vehs::identify::BinnedCurve& curve = checks[c].of(be);
      REQUIRE(curve.at.size() == static_cast<std::size_t>(kBins));
      for (std::size_t b = 0; b < curve.at.size(); ++b) {
        if (!(curve.rows[b] >= kMinRows) || !std::isfinite(curve.mean[b])) {
          usable[c][b] = false;
          continue;
        }
        const double dev = curve.mean[b] - checks[c].exact(curve.at[b]);
        sum[c][b] += dev;
        sum2[c][b] += dev * dev;
      }
    }
  }
  int m = 0;
  for (const auto& u : usable)
    for (bool ok : u) m += ok;
  CHECK(m >= 3 * kBins / 2);  // most bins hold enough rows in every replicate
  const double bound = vehs_test::t_bound(m, kReplicates - 1);
  double worst = 0.0;
  for (std::size_t c = 0; c < checks.size(); ++c)
    for (int b = 0; b < kBins; ++b) {
      if (!usable[c][static_cast<std::size_t>(b)]) continue;
      const double mean = sum[c][static_cast<std::size_t>(b)] / kReplicates;
      const double var = (sum2[c][static_cast<std::size_t>(b)] - kReplicates * mean * mean) / (kReplicates - 1);
      const double t = mean / std::sqrt(var / kReplicates);
      worst = std::max(worst, std::abs(t));
      CAPTURE(checks[c].curve, b, mean, std::sqrt(var / kReplicates));
      CHECK(std::abs(t) <= bound);
    }
  std::printf("binned estimates: %d bins checked, largest |t| %.2f (bound %.2f)\n", m, worst, bound);
}

TEST_CASE("binned diffusion is dropped when the sensor noise is nearly all of it", "[identify][binned]") {
  // white noise of sd 0.05 on x at h = 0.01: c·h·6s²/h⁴ ≈ 2e4 against a22 = 0.2, far over 95 %
  const vehs::Model truth = vehs::model_from_json(
      nlohmann::json{{"drift", {{"x", -1.0}, {"y", -0.5}}}, {"diffusion", {{"1", 0.2}}}}, "truth");
  vehs::Dataset d = vehs_test::simulate(truth, 0.01, 20, 1, 50000, 4321);
  std::mt19937_64 g(5);
  std::normal_distribution<double> z(0.0, 0.05);
  for (double& x : d.x.values()) x += z(g);
  vehs::identify::BinnedOptions o;
  o.bins = 20;
  o.noise_sd = 0.05;
  const auto be = vehs::identify::binned_estimates(d, truth, o);
  CHECK(be.noise_share > 0.99);
  CHECK(be.diffusion_bins_dropped > 10);
  for (double m : be.diffusion.mean) CHECK_FALSE(std::isfinite(m));
  o.noise_sd = 0.0;  // without the noise sd: the plateau, not a22
  const auto raw = vehs::identify::binned_estimates(d, truth, o);
  CHECK(raw.diffusion.mean[10] > 100 * 0.2);
}

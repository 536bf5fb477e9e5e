// diagnose evaluates the likelihood with the recorded input applied between samples the way the
// model was fitted (Model::fit->input; issue 12). Data: a driven Duffing with a smooth broadband
// input (a multisine, band-limited well below the Nyquist frequency), sampled at 10 samples per
// period of its resonance from a continuous process (the simulator steps 1/8 of a sample with the
// input at each step's midpoint; the recorded u is the input at the sampling instants). The model
// is fitted by the likelihood with the input band-limited, as identify-vehs does with
// `likelihood.input: "band_limited"`, and its fit information says so.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "vehs/core/model.hpp"
#include "vehs/diagnose/diagnose.hpp"
#include "vehs/diagnose/score_suspects.hpp"
#include "vehs/io/model_file.hpp"
#include "vehs/likelihood/refine.hpp"
#include "vehs/sim/simulate.hpp"

using namespace vehs;

namespace {

Model driven_duffing() {
  return model_from_json(nlohmann::json::parse(
                             R"({"drift": {"x": -1.0, "x^3": -0.5, "y": -0.15, "u": 1.0}, "diffusion": {"1": 0.002}})"),
                         "test model");
}

/// Sampling interval: 10 samples per period of the linear resonance (ω = 1).
constexpr double kDt = 2.0 * M_PI / 10.0;

/// u(t) = Σ_j a cos(ω_j t + φ_j), ω_j = 0.05 j (j = 1 … 40): band-limited to ω ≤ 2 (Nyquist 5).
struct Multisine {
  std::vector<double> phase;
  explicit Multisine(std::uint64_t seed) {
    std::mt19937_64 g(seed);
    std::uniform_real_distribution<double> ph(-M_PI, M_PI);
    for (int j = 0; j < 40; ++j) phase.push_back(ph(g));
  }
  double operator()(double t) const {
    double s = 0.0;
    for (std::size_t j = 0; j < phase.size(); ++j) s += 0.09 * std::cos(0.05 * double(j + 1) * t + phase[j]);
    return s;
  }
};

/// `records` records of n samples at dt: simulated at dt/8 with the input at every fine step's
/// midpoint, then every 8th sample kept; the recorded u is u(k·dt).
Dataset driven_data(const Model& m, double dt, std::size_t n, int records, double noise, std::uint64_t seed) {
  const int fine = 8;
  const double h = dt / fine;
  const Multisine u(seed);
  sim::SimulationOptions o;
  o.dt = h;
  o.substeps = 5;
  o.records = records;
  o.samples = (n - 1) * fine + 1;
  o.seed = seed;
  o.scheme = sim::Scheme::Taylor15;
  o.sensor_noise = noise;
  o.record_y = false;
  for (std::size_t j = 0; j < o.samples; ++j) o.drive.push_back(u((double(j) + 0.5) * h));
  const Dataset f = sim::simulate(m, o);
  Dataset d;
  for (const Record& r : f.records) {
    Record c = r;
    c.dt = dt;
    c.offset = d.x.size();
    c.size = n;
    for (std::size_t k = 0; k < n; ++k) {
      d.x.push_back(f.x_of(r)[k * fine]);
      d.u.push_back(u(double(k) * dt));
    }
    d.records.push_back(c);
  }
  return d;
}

/// The likelihood fit with the input band-limited, from the truth perturbed by 10 %, and the
/// fit information identify-vehs writes (sampling interval, sensor noise, input interpolation).
struct BandLimitedFit {
  Model model;
  double measurement_sd = 0.0;
};
BandLimitedFit fit_band_limited(const Dataset& d, double dt) {
  likelihood::ObservedModel start{driven_duffing(), 0.01, {}};
  for (auto& tc : start.model.drift) tc.coef *= 1.1;
  likelihood::RefineOptions ro;
  ro.filter.input = InputInterpolation::BandLimited;
  const likelihood::Result fit = likelihood::refine(start, d, ro);
  BandLimitedFit out{fit.model.model, fit.model.measurement_sd};
  out.model.fit = FitInfo{};
  out.model.fit->sampling.dt = dt;
  out.model.fit->sampling.sensor_noise_sd = fit.model.measurement_sd;
  out.model.fit->input = InputInterpolation::BandLimited;
  return out;
}

bool any_significant(const diagnose::ScoreSuspectReport& r) {
  for (const auto& s : r.ranked)
    if (s.significant) return true;
  return false;
}

std::string describe(const diagnose::ScoreSuspectReport& r) {
  std::string s = r.note;
  for (const auto& sp : r.ranked)
    s += "\n   " + sp.effect + ": z " + std::to_string(sp.z) + (sp.significant ? " (significant)" : "");
  return s;
}

}  // namespace

// False-failure probability per run: the suspects' family-wise claim rate under the model is
// alpha; at alpha = 1e-5 (Bonferroni over the effects inside score_suspects) the first check
// fails with probability ≤ 1e-5 when the model and its input interpolation are right. The second
// check is the power of the same tests against the half-sample delay of a held input (z ≫ 10
// here), not a rare event. Total ≤ 1e-4.
TEST_CASE("diagnose's likelihood applies the input as the model was fitted (band-limited): no suspect on "
          "the model's own driven data - held, the same model looks wrong",
          "[diagnose][score_suspects][input]") {
  const Dataset d = driven_data(driven_duffing(), kDt, 1500, 6, 0.01, 41);
  const BandLimitedFit fit = fit_band_limited(d, kDt);
  const Model& fitted = fit.model;

  diagnose::ScoreSuspectOptions so;
  so.alpha = 1e-5;
  const auto band = diagnose::score_suspects(fitted, d, fit.measurement_sd, so);
  INFO("band-limited:" << describe(band));
  CHECK(band.input == InputInterpolation::BandLimited);
  CHECK(band.note.empty());
  CHECK_FALSE(band.ranked.empty());
  CHECK_FALSE(any_significant(band));

  // the same model read as fitted with a held input: the filter's predictions lag the data
  Model held = fitted;
  held.fit->input = InputInterpolation::ZeroOrderHold;
  const auto zoh = diagnose::score_suspects(held, d, fit.measurement_sd, so);
  INFO("held:" << describe(zoh));
  CHECK(zoh.input == InputInterpolation::ZeroOrderHold);
  CHECK(any_significant(zoh));
}

// The whole diagnosis of the same fitted model on its own driven data: the interpolation reaches
// the likelihood through diagnose() and its score-suspects component passes. (The moment-based
// components — one-step map, drift and noise shape, residual spectrum — reject this model at 10
// samples per period: they are expansions in Δt, the limitation issue 12 describes for identify;
// diagnose's own area, not checked here.) False-failure probability: the component's p-value
// below the per-component threshold alpha/components = 1e-4/10 under the model.
TEST_CASE("diagnose: a driven model fitted with a band-limited input passes the likelihood's suspects "
          "component on its own driven data",
          "[diagnose][score_suspects][input][slow]") {
  const Dataset d = driven_data(driven_duffing(), kDt, 1500, 6, 0.01, 43);
  const Model fitted = fit_band_limited(d, kDt).model;
  diagnose::Options o;
  o.alpha = 1e-4;
  o.score_suspects.enabled = true;
  o.fpk = false;
  o.parameter_uncertainty = diagnose::ParameterUncertainty::Off;
  const diagnose::Result r = diagnose::diagnose(fitted, d, o);
  std::string why;
  const diagnose::Component* score = nullptr;
  for (const auto& c : r.components) {
    why += "\n   " + c.name + ": p " + std::to_string(c.test.p_value);
    if (c.name == "score_suspects") score = &c;
  }
  INFO("verdict components (threshold " << r.threshold << "):" << why << "\nsuspects:" << describe(r.score_suspects));
  CHECK(r.score_suspects.input == InputInterpolation::BandLimited);
  REQUIRE(score);
  CHECK(score->test.p_value >= r.threshold);
}

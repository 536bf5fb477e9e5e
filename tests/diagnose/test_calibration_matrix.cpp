// The verdict's calibration over data shapes (issue 13): the true model must be adequate on its
// own data for short and long records, few and many, scheme-consistent and continuous-time
// sampling. Small instances run in CI; the full matrix is a hidden bench tag:
//   VEHS_CAL_SEEDS=10 build/tests/test_diagnose "[.calibration_matrix]"
// (VEHS_CAL_SHAPE=text: only the shapes whose name contains it; VEHS_CAL_SEED0=k: seeds from k;
// VEHS_CAL_VERBOSE=1: every component's p-value and the twins; VEHS_CAL_FULL=1: with the suspects,
// the score suspects and the FPK reference, as diagnose-vehs runs; VEHS_CAL_BARE=1: the coarse
// shapes' true model without its likelihood section, the noise left to the sampling diagnosis;
// VEHS_CAL_FIT=1: the coarse shapes' model fitted as identify-vehs does there, likelihood_fit)
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <random>
#include <vector>

#include "../likelihood/likelihood_fixtures.hpp"
#include "diagnose_fixtures.hpp"
#include "vehs/identify/identify.hpp"
#include "vehs/likelihood/refine.hpp"
#include "vehs/likelihood/signals.hpp"

using namespace diag_test;

namespace {

enum class Truth {
  Paper,   ///< the bistable model of the fixtures (multiplicative noise), dt <= 0.05
  Issue12, ///< the bistable Duffing of issue 12 (U = -x^2/2 + x^4/4, beta = 0.1, 2D = 0.04)
  Driven,  ///< a driven Duffing with a recorded broadband input held between samples (a DAC)
  DrivenSmooth  ///< the same with a continuous input (recorded at the samples; fitted band-limited)
};

struct Shape {
  std::string name;
  int records;
  std::size_t samples;
  double dt;
  int substeps;  ///< 1: the paper's rk4_euler at the recorded step; > 1: continuous-time (Taylor 1.5)
  double burn_in;
  Truth truth = Truth::Paper;
  double noise_share = 0.0;  ///< white sensor noise, as a share of std(x)
};

/// The driven Duffing of bench/bench_likelihood.cpp `driven` (its input: a random-phase
/// multisine of 40 lines, spacing 0.05, amplitude 0.09 each).
vehs::Model driven_duffing() {
  return model_of(R"({"drift": {"x": -1.0, "x^3": -0.5, "y": -0.15, "u": 1.0}, "diffusion": {"1": 0.002}})");
}
vehs::Model truth_of(const Shape& s) {
  return s.truth == Truth::Paper ? bistable() : s.truth == Truth::Issue12 ? vehs_lik_test::bistable() : driven_duffing();
}

/// A continuous broadband input: Σ_j a·cos(j·dw·t + φ_j), 40 lines, dw 0.05, a 0.09 (the
/// spectrum of bench_likelihood's input, its own phases), below the Nyquist rate at 2π/10.
struct Multisine {
  std::vector<double> phase;
  explicit Multisine(std::uint64_t seed) {
    std::mt19937_64 g(seed);
    std::uniform_real_distribution<double> U(0.0, 2.0 * M_PI);
    for (int j = 0; j < 40; ++j) phase.push_back(U(g));
  }
  double operator()(double t) const {
    double s = 0.0;
    for (int j = 0; j < 40; ++j) s += 0.09 * std::cos((j + 1) * 0.05 * t + phase[std::size_t(j)]);
    return s;
  }
};

std::vector<Shape> shapes() {
  return {
      {"40 x 2000, dt 0.001, scheme, burn-in", 40, 2000, 0.001, 1, 50.0},
      {"40 x 2000, dt 0.001, scheme, no burn-in", 40, 2000, 0.001, 1, 0.0},
      {"40 x 2000, dt 0.01, continuous", 40, 2000, 0.01, 20, 50.0},
      {"100 x 500, dt 0.01, continuous", 100, 500, 0.01, 20, 50.0},
      {"8 x 20000, dt 0.01, continuous", 8, 20000, 0.01, 20, 50.0},
      {"4 x 50000, dt 0.02, continuous", 4, 50000, 0.02, 20, 50.0},
      {"32 x 6000, dt 0.05, continuous", 32, 6000, 0.05, 20, 50.0},
      {"200 x 1000, dt 0.001, scheme, burn-in", 200, 1000, 0.001, 1, 50.0},
      // coarse sampling (issue 12's likelihood range, omega*dt up to about 1)
      {"8 x 5714, dt 0.35, coarse continuous", 8, 5714, 0.35, 20, 50.0, Truth::Issue12},
      {"8 x 5714, dt 0.35, coarse continuous, 2 % noise", 8, 5714, 0.35, 20, 50.0, Truth::Issue12, 0.02},
      {"8 x 2857, dt 0.7, coarse continuous", 8, 2857, 0.7, 20, 50.0, Truth::Issue12},
      {"8 x 2857, dt 0.7, coarse continuous, 2 % noise", 8, 2857, 0.7, 20, 50.0, Truth::Issue12, 0.02},
      {"40 x 400, dt 0.7, coarse continuous, 2 % noise", 40, 400, 0.7, 20, 50.0, Truth::Issue12, 0.02},
      {"8 x 4000, dt 2pi/10, coarse driven, 2 % noise", 8, 4000, 2.0 * M_PI / 10.0, 40, 0.0, Truth::Driven, 0.02},
      {"8 x 4000, dt 2pi/10, coarse driven continuous input, 2 % noise", 8, 4000, 2.0 * M_PI / 10.0, 40, 0.0,
       Truth::DrivenSmooth, 0.02},
  };
}

/// The data of a shape and the sensor noise in them (the true model's measurement noise).
struct ShapeData {
  vehs::Dataset data;
  double noise = 0.0;
};

vehs::sim::SimulationOptions shape_options(const Shape& s, std::uint64_t seed) {
  vehs::sim::SimulationOptions o;
  o.dt = s.dt;
  o.substeps = s.substeps;
  o.scheme = s.substeps > 1 ? vehs::sim::Scheme::Taylor15 : vehs::sim::Scheme::Rk4Euler;
  o.records = s.records;
  o.samples = s.samples;
  o.burn_in = s.burn_in;
  o.record_y = false;
  o.seed = vehs_test::seed(seed);
  if (s.truth == Truth::Driven) {
    o.x0.lo = -1.5;
    o.x0.hi = 1.5;
    o.drive = vehs::likelihood::random_phase_multisine(s.samples, s.dt, 40, 0.05, 0.09, 3 + seed);
  }
  return o;
}

/// A continuous input u(t): simulated on the internal steps (input at each step's midpoint,
/// one step per sample), every substeps-th sample kept, u recorded at the sampling instants.
vehs::Dataset simulate_smooth_input(const vehs::Model& m, vehs::sim::SimulationOptions o, std::uint64_t seed) {
  const Multisine u(seed);
  const std::size_t n = o.samples, f = std::size_t(o.substeps);
  const double dt = o.dt, h = dt / double(f);
  o.drive.clear();
  for (std::size_t k = 0; k + 1 < n; ++k)
    for (std::size_t j = 0; j < f; ++j) o.drive.push_back(u((double(k) + (double(j) + 0.5) / double(f)) * dt));
  o.dt = h;
  o.substeps = 1;
  o.samples = (n - 1) * f + 1;
  const vehs::Dataset fine = vehs::sim::simulate(m, o);
  vehs::Dataset d;
  for (const auto& r : fine.records) {
    vehs::Record rec = r;
    rec.offset = d.x.size();
    rec.dt = dt;
    rec.size = n;
    for (std::size_t i = 0; i < n; ++i) {
      d.x.push_back(fine.x[r.offset + i * f]);
      d.u.push_back(u(double(i) * dt));
    }
    d.records.push_back(rec);
  }
  return d;
}

ShapeData shape_data(const Shape& s, std::uint64_t seed) {
  const vehs::Model m = truth_of(s);
  auto o = shape_options(s, seed);
  const auto run = [&](const vehs::sim::SimulationOptions& so) {
    return s.truth == Truth::DrivenSmooth ? simulate_smooth_input(m, so, 3 + seed) : vehs::sim::simulate(m, so);
  };
  ShapeData sd;
  if (s.noise_share > 0.0) {  // 2 % of std(x) of a pilot record, as bench_likelihood does
    auto pilot = o;
    pilot.records = 2;
    pilot.seed = o.seed + 1000003;
    sd.noise = s.noise_share * vehs_lik_test::sd_of(run(pilot).x);
  }
  o.sensor_noise = sd.noise;
  sd.data = run(o);
  return sd;
}

/// The true model; at coarse sampling as a likelihood fit writes it (identify-vehs uses the
/// likelihood there): a continuous-time model with its measurement noise.
vehs::Model observed_truth(const Shape& s, double noise) {
  vehs::Model m = truth_of(s);
  if (s.truth != Truth::Paper && !std::getenv("VEHS_CAL_BARE")) {
    vehs::FitInfo fit;
    fit.likelihood = vehs::LikelihoodFit{};
    fit.likelihood->measurement_sd = noise;
    if (s.truth == Truth::DrivenSmooth) fit.input = vehs::InputInterpolation::BandLimited;
    m.fit = fit;
  }
  return m;
}

std::string failing(const vehs::diagnose::Result& r) {
  std::string s;
  for (const auto& c : r.components)
    if (c.test.available && c.test.p_value < r.threshold * 10)
      s += " " + c.name + " p=" + std::to_string(c.test.p_value);
  return s;
}

/// diagnose's warning about a model without a likelihood fit at coarse sampling.
bool warns_bare_coarse(const vehs::diagnose::Result& r) {
  for (const auto& w : r.warnings)
    if (w.find("no likelihood fit") != std::string::npos) return true;
  return false;
}

/// The model identify-vehs writes at coarse sampling: the moment fit on the true model's terms,
/// refined by the likelihood (its measurement noise estimated where the data have noise), the
/// refinement recorded in the fit information as the tool does (VEHS_CAL_FIT=1).
vehs::Model likelihood_fit(const Shape& s, const ShapeData& d) {
  const vehs::Model truth = truth_of(s);
  vehs::identify::Options io;
  io.drift_library.clear();
  io.diffusion_library.clear();
  for (const auto& t : truth.drift) io.drift_library.push_back(t.term);
  for (const auto& t : truth.diffusion) io.diffusion_library.push_back(t.term);
  io.sparsity = vehs::identify::Sparsity::None;
  const vehs::Model start = vehs::identify::identify(d.data, io).model;
  vehs::likelihood::RefineOptions ro;
  ro.estimate_measurement_noise = d.noise > 0.0;
  if (s.truth == Truth::DrivenSmooth) ro.filter.input = vehs::InputInterpolation::BandLimited;
  const auto r = vehs::likelihood::refine({start, 0.0, {}}, d.data, ro);
  vehs::FitInfo fit = start.fit ? *start.fit : vehs::FitInfo{};
  fit.input = ro.filter.input;
  fit.likelihood = vehs::LikelihoodFit{};
  fit.likelihood->measurement_sd = r.model.measurement_sd;
  vehs::Model m = r.model.model;
  m.fit = fit;
  return m;
}

}  // namespace

TEST_CASE("calibration matrix: the true model on its own data, every shape (bench)", "[.calibration_matrix]") {
  const int seeds = std::getenv("VEHS_CAL_SEEDS") ? std::atoi(std::getenv("VEHS_CAL_SEEDS")) : 4;
  const char* only = std::getenv("VEHS_CAL_SHAPE");
  const int first = std::getenv("VEHS_CAL_SEED0") ? std::atoi(std::getenv("VEHS_CAL_SEED0")) : 1;
  for (const Shape& s : shapes()) {
    if (only && s.name.find(only) == std::string::npos) continue;
    int adequate = 0;
    for (int k = first; k < first + seeds; ++k) {
      const ShapeData d = shape_data(s, 7000 + std::uint64_t(k));
      auto o = fast_options(std::uint64_t(k));
      const bool full = std::getenv("VEHS_CAL_FULL") != nullptr;  // as diagnose-vehs runs
      o.suspects.enabled = full;
      o.score_suspects.enabled = full;
      o.fpk = full;
      const bool fitted = std::getenv("VEHS_CAL_FIT") && s.truth != Truth::Paper;
      const auto r = vehs::diagnose::diagnose(fitted ? likelihood_fit(s, d) : observed_truth(s, d.noise), d.data, o);
      adequate += r.adequate();
      std::printf("  %s seed %d: %s%s [lens %s, data sampling %s, sensor noise %.3g]\n", s.name.c_str(), k,
                  r.adequate() ? "adequate" : "INADEQUATE", failing(r).c_str(), r.lens.describe().c_str(),
                  vehs::enum_to_string(vehs::kSamplingVerdictNames, r.sampling.data_verdict).c_str(),
                  r.sampling.sensor_noise_sd);
      if (std::getenv("VEHS_CAL_VERBOSE"))
        std::printf("      twins: %s, %d substeps, %d replicates\n", vehs::enum_to_string(vehs::sim::kSchemeNames, r.sampling.twin_scheme).c_str(),
                    r.sampling.twin_substeps, r.sampling.replicates);
      if (std::getenv("VEHS_CAL_VERBOSE"))
        for (const auto& c : r.components)
          std::printf("      %-18s p=%.3g%s\n", c.name.c_str(), c.test.p_value, c.test.available ? "" : " (n/a)");
      std::fflush(stdout);
    }
    std::printf("%s: adequate %d of %d\n", s.name.c_str(), adequate, seeds);
  }
}

// CI instance: the shapes that failed before the one-step map's bins counted their effective
// units (short records: 40 × 2 time units of the paper's scheme; many short records of a
// continuous process), three seeds each. The verdict's family-wise false-alarm level is 1 %;
// granting a calibration error of 2× (2 %), P(Bin(6, 0.98) < binomial_floor(6, 0.98)) ≤ 1e-4.
// Before the fix: 1 of 3 adequate on the first shape (one_step p = 2e-6, < 1e-6).
TEST_CASE("calibration matrix: short records, scheme-consistent and continuous-time", "[diagnose][calibration]") {
  int adequate = 0, runs = 0;
  for (const Shape& s : shapes()) {
    if (s.name != "40 x 2000, dt 0.001, scheme, burn-in" && s.name != "100 x 500, dt 0.01, continuous") continue;
    for (int k = 1; k <= 3; ++k) {
      const vehs::Dataset d = shape_data(s, 7100 + std::uint64_t(k)).data;
      auto o = fast_options(std::uint64_t(k));
      o.suspects.enabled = false;
      o.fpk = false;
      const auto r = vehs::diagnose::diagnose(bistable(), d, o);
      UNSCOPED_INFO(s.name << " seed " << k << ": " << (r.adequate() ? "adequate" : "INADEQUATE") << failing(r));
      CHECK_FALSE(warns_bare_coarse(r));  // fine sampling: ω̂·Δt ≤ 0.07
      adequate += r.adequate();
      ++runs;
    }
  }
  CHECK(runs == 6);
  CHECK(adequate >= vehs_test::binomial_floor(6, 0.98));
}

// CI instance at coarse sampling (omega*dt up to about 1, issue 12's likelihood range): the true
// model as identify-vehs's likelihood writes it (continuous time, its measurement noise, the
// input interpolation it was fitted with), five seeds of the five shapes with sensor noise.
// Measured over 30 bench seeds of the seven coarse shapes: 205 of 210 adequate (2.4 % false
// alarms against the verdict's nominal 1 %; seed 22 of dt 0.35 fails with and without noise);
// granting 4 % per run,
// P(Bin(25, 0.96) < binomial_floor(25, 0.96) = 19) = 4e-5 <= 1e-4 (at most 6 of 25 may fail).
// Before the fixes: 2 of 20 adequate on the first four shapes (twins by the moment pilot's
// reading — the paper's scheme at the recorded step at dt 0.7 — and 10 substeps); 0 of 10 on
// the continuous input with the input held between samples in the twins.
TEST_CASE("calibration matrix: coarse sampling, continuous-time with sensor noise and a recorded input",
          "[diagnose][calibration]") {
  int adequate = 0, runs = 0;
  for (const Shape& s : shapes()) {
    if (s.truth == Truth::Paper || (s.noise_share == 0.0)) continue;
    for (int k = 1; k <= 5; ++k) {
      const ShapeData d = shape_data(s, 7100 + std::uint64_t(k));
      auto o = fast_options(std::uint64_t(k));
      o.suspects.enabled = false;
      o.fpk = false;
      const auto r = vehs::diagnose::diagnose(observed_truth(s, d.noise), d.data, o);
      UNSCOPED_INFO(s.name << " seed " << k << ": " << (r.adequate() ? "adequate" : "INADEQUATE") << failing(r));
      adequate += r.adequate();
      ++runs;
      CHECK_FALSE(warns_bare_coarse(r));  // the likelihood fit states its measurement noise
    }
  }
  // the same model written without its likelihood fit (VEHS_CAL_BARE: adequate 0 of 10 at dt 0.7
  // with noise) is warned about: ω̂·Δt ≈ 1 there against the warning's 0.2 (deterministic margin)
  {
    Shape s{};
    for (const Shape& c : shapes())
      if (c.name == "8 x 2857, dt 0.7, coarse continuous, 2 % noise") s = c;
    REQUIRE(s.records == 8);
    const ShapeData d = shape_data(s, 7101);
    auto o = fast_options(1);
    o.suspects.enabled = false;
    o.fpk = false;
    o.score_suspects.enabled = false;
    const auto r = vehs::diagnose::diagnose(truth_of(s), d.data, o);
    INFO(s.name);
    CHECK(warns_bare_coarse(r));
  }
  CHECK(runs == 25);
  CHECK(adequate >= vehs_test::binomial_floor(25, 0.96));
}

// The sampling diagnosis behind the lens (identify's pilot with the model's terms, as
// diagnose's sampling pilot runs it) on the matrix's 200 × 1000 scheme data, seed 5: lag 2k
// alone read 5.9 % sensor noise there (a 3-sigma excess at lag 2k; ρ_k ≈ 0 contradicts it) and
// the true model failed every residual component. With lags k and 2k together the rule's
// standard error is 0.0036 on these 2·10⁵ rows: a false "noisy" needs 14 standard errors, and
// white noise of share ≈ 0.19 (s = 1e-6) is read at 40 of them — the checks cannot fail by
// chance (deterministic data; margins > 10 standard errors).
TEST_CASE("calibration matrix: many short scheme records are read as scheme-consistent, with sensor noise as noisy",
          "[diagnose][calibration][sampling]") {
  Shape s{};
  for (const Shape& c : shapes())
    if (c.name == "200 x 1000, dt 0.001, scheme, burn-in") s = c;
  REQUIRE(s.records == 200);
  vehs::Dataset d = shape_data(s, 7005).data;
  vehs::identify::Options o;
  o.drift_library = {vehs::Term::monomial(1, 0), vehs::Term::monomial(3, 0), vehs::Term::monomial(0, 1)};
  o.diffusion_library = {vehs::Term::monomial(0, 0), vehs::Term::monomial(2, 0)};
  o.sparsity = vehs::identify::Sparsity::None;
  o.folds = 1;
  auto read = [&](const vehs::Dataset& data) { return *vehs::identify::identify(data, o).model.fit; };
  const vehs::FitInfo clean = read(d);
  INFO("rho_k " << clean.sampling.rho_k << " rho_2k " << clean.sampling.rho_2k << " rho_3k " << clean.sampling.rho_3k);
  CHECK(clean.sampling.verdict == vehs::SamplingVerdict::SchemeConsistent);
  CHECK(clean.sampling.noise_share < 0.02);
  std::mt19937_64 rng(vehs_test::seed(5));
  std::normal_distribution<double> noise(0.0, 1e-6);
  for (double& x : d.x) x += noise(rng);
  const vehs::FitInfo noisy = read(d);
  CHECK(noisy.sampling.verdict == vehs::SamplingVerdict::Noisy);
  CHECK(noisy.sampling.noise_share > 0.1);
}

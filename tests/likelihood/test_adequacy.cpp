// The rule of estimator "auto" (vehs/likelihood/adequacy.hpp) beyond ω̂Δt: white sensor noise at
// the recorded rate, noise white only at a longer stride, and hidden states. Deterministic:
// a slow cosine (ω̂Δt 0.05) and models whose fit info states what identify would have found.
#include <catch2/catch.hpp>

#include <cmath>

#include "vehs/io/model_file.hpp"
#include "vehs/likelihood/adequacy.hpp"

using namespace vehs;

namespace {

Dataset cosine(double dt, double omega_dt) {
  Dataset d;
  Record r;
  r.dt = dt;
  r.size = 4000;
  d.records.push_back(r);
  for (std::size_t k = 0; k < r.size; ++k) d.x.push_back(std::cos(omega_dt * double(k)));
  return d;
}

Dataset slow_cosine(double dt) { return cosine(dt, 0.05); }

/// A bistable fit with β's relative SE 2 % and the sampling diagnosis given.
Model fit_with(SamplingVerdict verdict, int stride) {
  Model m;
  m.drift = {{Term::parse("x"), 1.0}, {Term::parse("x^3"), -1.0}, {Term::parse("y"), -0.1}};
  m.diffusion = {{Term::parse("1"), 0.04}};
  m.drift_stderr = {{"x", 0.02}, {"x^3", 0.02}, {"y", 0.002}};
  FitInfo f;
  f.sampling.verdict = verdict;
  f.sampling.stride = stride;
  f.sampling.noise_share = 0.9;
  m.fit = f;
  return m;
}

}  // namespace

TEST_CASE("auto: white sensor noise at the recorded rate sends the fit to the likelihood - noise "
          "white only at a longer stride does not", "[likelihood][adequacy]") {
  const Dataset d = slow_cosine(0.05);
  const likelihood::SamplingAdequacy scheme = likelihood::assess_sampling(fit_with(SamplingVerdict::ContinuousTime, 1), d);
  CHECK(scheme.vouched);
  const likelihood::SamplingAdequacy noisy = likelihood::assess_sampling(fit_with(SamplingVerdict::Noisy, 1), d);
  CHECK_FALSE(noisy.vouched);
  CHECK(noisy.reason.find("white sensor noise") != std::string::npos);
  const likelihood::SamplingAdequacy quantised = likelihood::assess_sampling(fit_with(SamplingVerdict::Noisy, 2), d);
  CHECK(quantised.vouched);
}

TEST_CASE("auto: a hidden state's moment fit stands only while 2·rate·Δt is below the best "
          "relative SE", "[likelihood][adequacy]") {
  const Dataset d = slow_cosine(0.05);
  for (const char* effect : {R"({"name": "electromechanical_coupling", "params": {"lambda": 0.8, "coupling": 0.5}})",
                             R"({"name": "colored_noise", "params": {"tau": 0.6, "intensity": 0.04}})"}) {
    Model m = fit_with(SamplingVerdict::ContinuousTime, 1);
    const Model with = model_from_json(
        nlohmann::json::parse(std::string(R"({"drift": {"x": 1}, "diffusion": {"1": 0.04}, "effects": [)") + effect + "]}"),
        "effect");
    m.effects = with.effects;
    INFO(effect);
    // rate·Δt 0.04 (λ 0.8) or 0.083 (τ 0.6): 2·rate·Δt far above the best relative SE 0.02
    const likelihood::SamplingAdequacy a = likelihood::assess_sampling(m, d);
    CHECK_FALSE(a.vouched);
    CHECK(a.reason.find("hidden state") != std::string::npos);
    // the same at Δt 0.001 (2·rate·Δt 0.0016–0.0033 < 0.02): the moment fit stands
    CHECK(likelihood::assess_sampling(m, slow_cosine(0.001)).vouched);
  }
  CHECK(likelihood::hidden_state_rate_dt(fit_with(SamplingVerdict::ContinuousTime, 1), 0.05) == 0.0);
}

TEST_CASE("auto: from 0.2 radians per sample the likelihood refines whatever the standard errors - "
          "below, only a bias above the best relative SE", "[likelihood][adequacy]") {
  Model m = fit_with(SamplingVerdict::ContinuousTime, 1);  // best relative SE 0.02
  const likelihood::SamplingAdequacy coarse = likelihood::assess_sampling(m, cosine(0.05, 0.29));
  CHECK(coarse.omega_dt == Approx(0.29).epsilon(1e-3));
  CHECK(coarse.bias < 0.02);  // the former rule vouched here
  CHECK_FALSE(coarse.vouched);
  CHECK(likelihood::assess_sampling(m, cosine(0.05, 0.15)).vouched);  // bias 0.0019 < 0.02
  m.drift_stderr = {{"x", 0.001}, {"x^3", 0.001}, {"y", 0.0001}};      // best relative SE 0.001
  CHECK_FALSE(likelihood::assess_sampling(m, cosine(0.05, 0.15)).vouched);
  CHECK(likelihood::assess_sampling(m, cosine(0.05, 0.05)).vouched);   // bias 2e-4 < 0.001
}

TEST_CASE("auto: the rule's frequency is the larger of the increments' and the fitted drift's "
          "stiffness over the data (the wells' frequency that hopping hides)", "[likelihood][adequacy]") {
  // a bistable's x: the variance is mostly the hopping between wells at ±1, so the increments
  // read a low frequency (here a slow cosine of amplitude 1.2, ω̂Δt 0.02 at Δt 0.35), while the
  // wells ring at √2 (ω·Δt 0.5): the fitted drift x − x³ has stiffness 3x² − 1 there. An outside
  // run of issue 12's case at Δt 0.35 had ω̂Δt 0.165, the moment fit vouched for, and a diffusion
  // x² term at z −13.3 written (bench/identify_coarse_cli.py).
  Model m = fit_with(SamplingVerdict::ContinuousTime, 1);
  m.drift_stderr = {{"x", 0.001}, {"x^3", 0.001}, {"y", 0.0001}};
  Dataset d = cosine(0.35, 0.02);
  for (double& x : d.x) x *= 1.2;
  // ω_s² = mean of max(3x² − 1, 0) over x = 1.2 cos θ, by quadrature over θ
  double sum = 0.0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double x = 1.2 * std::cos(2.0 * M_PI * (i + 0.5) / n);
    sum += std::max(3.0 * x * x - 1.0, 0.0);
  }
  const double expected = std::sqrt(sum / n) * 0.35;
  const likelihood::SamplingAdequacy a = likelihood::assess_sampling(m, d);
  CHECK(a.increments_omega_dt == Approx(0.02).epsilon(1e-2));
  // 4000 samples of a cosine over 12.7 periods: the sample mean within 1 % of the period's
  CHECK(a.stiffness_omega_dt == Approx(expected).epsilon(1e-2));
  CHECK(a.omega_dt == a.stiffness_omega_dt);
  CHECK(a.omega_dt > 0.2);
  CHECK_FALSE(a.vouched);
  CHECK(a.reason.find("stiffness") != std::string::npos);
  // the same data finely sampled (Δt 0.01): both frequencies small, vouched
  for (auto& r : d.records) r.dt = 0.01;
  const likelihood::SamplingAdequacy fine = likelihood::assess_sampling(m, d);
  CHECK(fine.stiffness_omega_dt == Approx(expected * 0.01 / 0.35).epsilon(1e-2));
  CHECK(fine.vouched);
}

TEST_CASE("auto: an input that changes fast sends the fit to the likelihood when its half-step "
          "phase error exceeds the best relative SE", "[likelihood][adequacy]") {
  // a slow x (ω̂Δt 0.05) driven by a faster input: a closed loop's controller force changes by
  // about 11 % of its spread per sample while the axis moves slowly (bench/positioning_rig.py)
  Model m = fit_with(SamplingVerdict::ContinuousTime, 1);  // best relative SE 0.02
  m.drift.push_back({Term::drive(), 1.0});
  Dataset d = slow_cosine(0.05);
  const double omega_u_dt = 0.12;
  for (std::size_t k = 0; k < d.x.size(); ++k) d.u.push_back(3.0 + std::sin(omega_u_dt * double(k)));
  // rms(Δu)/sd(u) of a sinusoid is 2 sin(ωΔt/2) (exactly, over whole periods; 4000 samples hold
  // 76.4 periods, so within 0.2 %)
  CHECK(likelihood::input_omega_dt(d) == Approx(2.0 * std::sin(omega_u_dt / 2)).epsilon(2e-3));
  {  // the same input on an offset of 1e8 (raw counts): E[u²] − E[u]² would lose it entirely
    Dataset far = d;
    for (double& v : far.u) v += 1e8;
    CHECK(likelihood::input_omega_dt(far) == Approx(2.0 * std::sin(omega_u_dt / 2)).epsilon(2e-3));
  }
  const likelihood::SamplingAdequacy fast = likelihood::assess_sampling(m, d);  // phase 0.06 > 0.02
  CHECK(fast.input_omega_dt == likelihood::input_omega_dt(d));
  CHECK_FALSE(fast.vouched);
  CHECK(fast.reason.find("input that changes fast") != std::string::npos);
  // the same input at a tenth of the rate: phase error 0.006 < 0.02, the moment fit stands
  for (std::size_t k = 0; k < d.x.size(); ++k) d.u[k] = 3.0 + std::sin(0.1 * omega_u_dt * double(k));
  CHECK(likelihood::assess_sampling(m, d).vouched);
  // no input term in the model: the input's rate is not the model's concern
  m.drift.pop_back();
  for (std::size_t k = 0; k < d.x.size(); ++k) d.u[k] = 3.0 + std::sin(omega_u_dt * double(k));
  CHECK(likelihood::assess_sampling(m, d).vouched);
  CHECK(likelihood::input_omega_dt(Dataset{}) == 0.0);
}

TEST_CASE("auto: a moment fit that resolved no drift coefficient is not vouched for", "[likelihood][adequacy]") {
  // (a quantised closed-loop record gave beta = mu = 0 and dropped the input: nothing bounds the
  // expansions' bias, so the likelihood refits from every start)
  Model m = fit_with(SamplingVerdict::ContinuousTime, 1);
  CHECK(likelihood::assess_sampling(m, slow_cosine(0.001)).vouched);
  for (auto& tc : m.drift) tc.coef = 0.0;
  const likelihood::SamplingAdequacy zero = likelihood::assess_sampling(m, slow_cosine(0.001));
  INFO(zero.reason);
  CHECK_FALSE(zero.vouched);
  CHECK(zero.reason.find("resolved no drift coefficient") != std::string::npos);
  m.drift.clear();
  CHECK_FALSE(likelihood::assess_sampling(m, slow_cosine(0.001)).vouched);
}

// Dynamic effects fitted by the same likelihood: an electromechanical hidden state, a coloured
// (Ornstein–Uhlenbeck) excitation, and harmonic forcing of records started at unrelated times
// (one phase per record, amplitude and frequency shared). Records simulated from continuous time
// (40 internal steps per sample, Δt = 0.25, 1 % sensor noise) with parameters the fit never
// sees; the start is the truth perturbed by 20 %. Each effect parameter within its standard
// errors and 15 %, the other parameters within their standard errors.
#include <catch2/catch.hpp>

#include <cmath>

#include "likelihood_fixtures.hpp"
#include "vehs/likelihood/refine.hpp"

using namespace vehs;
using namespace vehs_lik_test;

namespace {

Effect effect(EffectId id, std::map<std::string, double> params) {
  Effect e;
  e.id = id;
  e.params = std::move(params);
  return e;
}

likelihood::ObservedModel perturbed(const likelihood::ObservedModel& truth) {
  likelihood::ObservedModel s = truth;
  for (auto& tc : s.model.drift) tc.coef *= 1.2;
  for (auto& tc : s.model.diffusion) tc.coef *= 0.8;
  // (a frequency only by 0.1 %: the likelihood in ω has side lobes every 2π/T_record, so a
  // start must lie in the main lobe — identify's spectral scan provides one)
  for (auto& e : s.model.effects)
    for (auto& [k, v] : e.params)
      if (k != "phase") v *= k == "omega" ? 1.001 : 1.2;
  s.measurement_sd *= 1.5;
  return s;
}

/// Every parameter within z SE; effect parameters also within 15 %.
void check_fit(const likelihood::Result& r, const likelihood::ObservedModel& truth, double z) {
  std::map<std::string, double> all, effects;
  for (const auto& tc : truth.model.drift) all["drift[" + tc.term.name() + "]"] = tc.coef;
  for (const auto& tc : truth.model.diffusion) all["diffusion[" + tc.term.name() + "]"] = tc.coef;
  for (const auto& e : truth.model.effects)
    for (const auto& [k, v] : e.params)
      if (r.find(e.name() + "." + k) >= 0) all[e.name() + "." + k] = effects[e.name() + "." + k] = v;
  all["measurement_sd"] = truth.measurement_sd;
  const Check c = against(r, all);
  CHECK(c.max_z <= z);
  for (const auto& [name, v] : effects) {
    const double rel = std::abs(r.values[std::size_t(r.find(name))] - v) / std::abs(v);
    INFO(name << " relative error " << rel);
    CHECK(rel <= 0.15);
  }
}

}  // namespace

// False-failure probability per run ≤ 1e-4: seven parameters, each outside z_bound(7) ≈ 4.6 SE
// with probability 1.4e-5; the 15 % bounds are 5 SE or more (SE ≤ 3 % measured).
TEST_CASE("electromechanical coupling by the likelihood", "[likelihood][effects][slow]") {
  likelihood::ObservedModel truth{bistable(), 0.01, {}};
  truth.model.effects = {effect(EffectId::ElectromechanicalCoupling, {{"lambda", 0.6}, {"coupling", 0.4}})};
  const Dataset d = simulate(truth.model, 0.25, 6, 1500.0, 41, truth.measurement_sd);
  const auto r = likelihood::refine(perturbed(truth), d);
  INFO(r.summary.FullReport());
  check_fit(r, truth, z_bound(7));
}

// False-failure probability per run ≤ 1e-4: seven parameters (z_bound(7)), 15 % ≥ 5 SE.
TEST_CASE("coloured (OU) excitation by the likelihood", "[likelihood][effects][slow]") {
  likelihood::ObservedModel truth{
      model(R"({"drift": {"x": -1.0, "x^3": -1.0, "y": -0.2}, "diffusion": {"1": 0.005}})"), 0.01, {}};
  truth.model.effects = {effect(EffectId::ColoredNoise, {{"tau", 1.0}, {"intensity", 0.04}})};
  const Dataset d = simulate(truth.model, 0.25, 8, 2500.0, 42, truth.measurement_sd);
  const auto r = likelihood::refine(perturbed(truth), d);
  INFO(r.summary.FullReport());
  check_fit(r, truth, z_bound(7));
}

// False-failure probability per run ≤ 1e-4: 6 shared parameters and 6 phases, each outside
// z_bound(12) ≈ 4.75 SE with probability 8e-6; 15 % ≥ 5 SE.
TEST_CASE("harmonic forcing with one phase per record by the likelihood", "[likelihood][effects][slow]") {
  const double phases[] = {0.3, -2.0, 1.4, 2.9, -0.7, -2.8};
  likelihood::ObservedModel truth{bistable(), 0.01, {}};
  truth.model.effects = {effect(EffectId::HarmonicForcing, {{"amplitude", 0.12}, {"omega", 0.8}, {"phase", 0.0}})};
  Dataset d;
  for (int r = 0; r < 6; ++r) {
    Model m = truth.model;
    m.effects[0].params["phase"] = phases[r];
    truth.record_phases.push_back(phases[r]);
    Dataset one = simulate(m, 0.25, 1, 1500.0, 43 + std::uint64_t(r), truth.measurement_sd);
    d.append(std::move(one));
  }
  likelihood::ObservedModel start = perturbed(truth);
  for (auto& p : start.record_phases) p += 0.2;
  likelihood::RefineOptions o;
  o.per_record_phase = true;
  const auto r = likelihood::refine(start, d, o);
  INFO(r.summary.FullReport());
  check_fit(r, truth, z_bound(12));
  for (int i = 0; i < 6; ++i) {
    const int k = r.find("phase[" + std::to_string(i) + "]");
    REQUIRE(k >= 0);
    const double se = r.stderrs[std::size_t(k)];
    const double dphi = std::remainder(r.values[std::size_t(k)] - phases[i], 2.0 * M_PI);
    INFO("phase " << i << ": " << r.values[std::size_t(k)] << " +- " << se << " (true " << phases[i] << ")");
    CHECK(std::abs(dphi) <= z_bound(12) * se);
  }
}

// An outside tester's coupled bistable (β 0.1, λ 1, coupling 0.15; 32 records × 5000 samples at
// Δt 0.05): the selection removed y at 2ΔlogL below the threshold and the electromechanical
// state took the damping's place along its ridge (−κv is a damping κ/λ when λ ≫ ω): β 0,
// coupling 6.6 SE and λ 4.1 SE from the truth, judged adequate. The selection now keeps x and y
// beside that state (likelihood/selection.cpp). Here the same model on 8 records at Δt 0.1 with
// the selection on: y kept, and λ and the coupling within z_bound(7) SE (false failure ≤ 1e-4).
TEST_CASE("the selection keeps the damping beside an electromechanical state", "[likelihood][effects][selection]") {
  likelihood::ObservedModel truth{bistable(), 0.0, {}};
  truth.model.effects = {effect(EffectId::ElectromechanicalCoupling, {{"lambda", 1.0}, {"coupling", 0.15}})};
  const Dataset d = simulate(truth.model, 0.1, 8, 1000.0, 4417);
  likelihood::RefineOptions o;
  o.select = true;
  o.estimate_measurement_noise = false;
  const auto r = likelihood::refine(truth, d, o);
  INFO(r.summary.FullReport());
  CHECK(r.find("drift[y]") >= 0);
  CHECK(r.find("drift[x]") >= 0);
  const Check c = against(r, {{"electromechanical_coupling.lambda", 1.0}, {"electromechanical_coupling.coupling", 0.15}});
  CHECK(c.max_z <= z_bound(7));
}

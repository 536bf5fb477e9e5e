#pragma once
// Hidden-effect data sets of issue 13 for the score-test suspects: bi-, tri- and penta-stable
// potentials, one catalogue effect hidden with the issue's parameters, continuous-time records
// (Taylor 1.5, 20 substeps per sample, a burn-in) sampled as a sensor would, 25–40 records. The
// code under test sees only the records; its baseline is the potential's terms fitted by identify.
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "vehs/core/model.hpp"
#include "vehs/identify/identify.hpp"
#include "vehs/io/model_file.hpp"
#include "vehs/sim/simulate.hpp"
#include "stat_bounds.hpp"

namespace score_test {

enum class Potential { Bistable, Tristable, Pentastable };

/// The potential's restoring terms (drift = −U'(x)) as JSON members.
inline std::string potential_terms(Potential p) {
  switch (p) {
    case Potential::Bistable: return R"J("x": 1.0, "x^3": -1.0)J";
    case Potential::Tristable: return R"J("x": -1.0, "x^3": 2.5, "x^5": -1.0)J";  // wells 0, ±√2
    case Potential::Pentastable:  // U' = x(x²−1)(x²−2.25)(x²−4)(x²−6.25)/20: wells 0, ±1.5, ±2.5
      return R"J("x": -2.8125, "x^3": 5.215625, "x^5": -3.028125, "x^7": 0.675, "x^9": -0.05)J";
  }
  return "";
}

inline std::vector<std::string> potential_library(Potential p) {
  switch (p) {
    case Potential::Bistable: return {"x", "x^3"};
    case Potential::Tristable: return {"x", "x^3", "x^5"};
    case Potential::Pentastable: return {"x", "x^3", "x^5", "x^7", "x^9"};
  }
  return {};
}

struct HiddenCase {
  std::string name;       ///< the case: the hidden effect ("none": control), "<effect>_weak" or "<effect>_slow"
  std::string hidden;     ///< the hidden effect when the name is not it (a weak or slow case); else ""
  Potential potential = Potential::Bistable;
  double beta = 0.1, two_d = 0.04;
  std::string effect;     ///< JSON of the effects array entry ("" : none)
  std::string extra_drift, extra_diffusion;  ///< term-like effects as JSON members
  bool phase_per_record = false;             ///< harmonic forcing: random phase per record
  int records = 32;
  std::size_t samples = 4000;
  double dt = 0.05;
  double sensor_noise_share = 0.0;  ///< white sensor noise, share of std(x) (coarse shape)

  const std::string& effect_name() const { return hidden.empty() ? name : hidden; }
  bool weak() const { return name.size() > 5 && name.compare(name.size() - 5, 5, "_weak") == 0; }
};

/// The coarse shape of issue 13's power study (VEHS_SCORE_COARSE=1): the same records sampled at
/// Δt 0.35 (ω·Δt ≈ 0.5; the same duration, 1/7 of the samples) with white sensor noise of 2 % of
/// std(x); the baseline and the oracle then fitted by the likelihood with the measurement noise.
inline HiddenCase coarse(HiddenCase c) {
  c.samples = static_cast<std::size_t>(std::lround(double(c.samples) * c.dt / 0.35));
  c.dt = 0.35;
  c.sensor_noise_share = 0.02;
  return c;
}

inline vehs::Model truth_of(const HiddenCase& c, double phase = 0.0) {
  std::string drift = potential_terms(c.potential) + ", \"y\": " + std::to_string(-c.beta);
  if (!c.extra_drift.empty()) drift += ", " + c.extra_drift;
  std::string diffusion = "\"1\": " + std::to_string(c.two_d);
  if (!c.extra_diffusion.empty()) diffusion += ", " + c.extra_diffusion;
  std::string effects = c.effect;
  if (c.phase_per_record) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", phase);
    effects += std::string(", \"phase\": ") + buf + "}}";
  }
  const std::string json = "{\"drift\": {" + drift + "}, \"diffusion\": {" + diffusion + "}, \"effects\": [" +
                           effects + "]}";
  return vehs::model_from_json(nlohmann::json::parse(json), "hidden-effect truth");
}

/// The cases of issue 13's table (parameters from the issue; potentials varied).
inline std::vector<HiddenCase> hidden_cases() {
  std::vector<HiddenCase> v;
  auto add = [&](HiddenCase c) { v.push_back(std::move(c)); };
  auto make = [](const std::string& name, Potential p, double beta = 0.1, double two_d = 0.04) {
    HiddenCase c;
    c.name = name;
    c.potential = p;
    c.beta = beta;
    c.two_d = two_d;
    return c;
  };
  add(make("none", Potential::Bistable));
  add(make("none_tristable", Potential::Tristable, 0.1, 0.05));
  add(make("none_pentastable", Potential::Pentastable, 0.1, 0.2));
  {
    HiddenCase c = make("coulomb_friction", Potential::Bistable);
    c.extra_drift = "\"sign(y)\": -0.03";
    add(c);
  }
  {
    HiddenCase c = make("quadratic_damping", Potential::Tristable, 0.1, 0.05);
    c.extra_drift = R"J("y*|y|": -0.3)J";
    add(c);
  }
  {
    HiddenCase c = make("nonlinear_damping", Potential::Bistable);
    c.extra_drift = R"J("y^3": -0.3)J";
    add(c);
  }
  {
    HiddenCase c = make("velocity_dependent_noise", Potential::Pentastable, 0.1, 0.2);
    c.extra_diffusion = R"J("y^2": 0.1)J";
    add(c);
  }
  {
    HiddenCase c = make("colored_noise", Potential::Bistable);
    c.effect = R"J({"name": "colored_noise", "params": {"tau": 0.6, "intensity": 0.04}})J";
    c.two_d = 0.01;
    add(c);
  }
  {
    HiddenCase c = make("electromechanical_coupling", Potential::Bistable);
    c.effect = R"J({"name": "electromechanical_coupling", "params": {"lambda": 0.8, "coupling": 0.5}})J";
    add(c);
  }
  {
    HiddenCase c = make("impact_stop", Potential::Tristable, 0.1, 0.05);
    c.effect = R"J({"name": "impact_stop", "params": {"k_stop": 5.0, "gap": 1.6}})J";
    add(c);
  }
  {
    HiddenCase c = make("harmonic_forcing", Potential::Bistable);
    c.effect = R"J({"name": "harmonic_forcing", "params": {"amplitude": 0.08, "omega": 0.9, "phase": 0.3}})J";
    add(c);
  }
  {
    HiddenCase c = make("harmonic_forcing_per_record", Potential::Bistable);
    c.effect = R"J({"name": "harmonic_forcing", "params": {"amplitude": 0.08, "omega": 0.9)J";
    c.phase_per_record = true;
    add(c);
  }
  // Slow versions (issue 13's untested look-alikes): a forcing well below the wells' frequency
  // (ω 0.1 against ≈ 1.4; ≈ 3 periods a record), shared phase and one phase per record, and an OU
  // excitation of long memory (τ = 5). The forcing's amplitude: its likelihood information is
  // T/(2D)/2 whatever ω, so 0.05 gives an oracle z of ≈ 14 on these 32 × 200 time units.
  {
    HiddenCase c = make("harmonic_forcing_slow", Potential::Bistable);
    c.hidden = "harmonic_forcing";
    c.effect = R"J({"name": "harmonic_forcing", "params": {"amplitude": 0.05, "omega": 0.1, "phase": 0.3}})J";
    add(c);
  }
  {
    HiddenCase c = make("harmonic_forcing_per_record_slow", Potential::Bistable);
    c.hidden = "harmonic_forcing_per_record";
    c.effect = R"J({"name": "harmonic_forcing", "params": {"amplitude": 0.05, "omega": 0.1)J";
    c.phase_per_record = true;
    add(c);
  }
  {  // the per-record slow forcing at an oracle z of ≈ 7: where the OU excitation's one-parameter
     // test gains on the 2R-dof per-record scan (both z's near the claim threshold)
    HiddenCase c = make("harmonic_forcing_per_record_slow_a025", Potential::Bistable);
    c.hidden = "harmonic_forcing_per_record";
    c.effect = R"J({"name": "harmonic_forcing", "params": {"amplitude": 0.025, "omega": 0.1)J";
    c.phase_per_record = true;
    add(c);
  }
  for (const char* tau : {"20", "50"}) {  // OU memory beyond the colored_noise scan's longest τ (10/ω̄ ≈ 8)
    HiddenCase c = make(std::string("colored_noise_slow_tau") + tau, Potential::Bistable);
    c.hidden = "colored_noise";
    c.effect = std::string(R"J({"name": "colored_noise", "params": {"tau": )J") + tau + R"J(, "intensity": 0.04}})J";
    c.two_d = 0.01;
    add(c);
  }
  {
    HiddenCase c = make("colored_noise_slow", Potential::Bistable);
    c.hidden = "colored_noise";
    c.effect = R"J({"name": "colored_noise", "params": {"tau": 5.0, "intensity": 0.04}})J";
    c.two_d = 0.01;
    add(c);
  }
  // Weak versions ("<effect>_weak"): the same set-ups with the effect scaled to an oracle z of
  // about 1.5 (z scales with the effect's size there: 1/5 or less of the strong cases' 7–22),
  // for the issue's "where the oracle z is <= 2, no claim in >= 95 % of seeds".
  auto weak = [&](const std::string& effect, const std::string& from, const std::string& to) {
    for (HiddenCase c : std::vector<HiddenCase>(v)) {
      if (c.name != effect) continue;
      c.hidden = c.name;
      c.name += "_weak";
      std::string* field = c.effect.empty() ? (c.extra_drift.empty() ? &c.extra_diffusion : &c.extra_drift) : &c.effect;
      const std::size_t at = field->find(from);
      if (at == std::string::npos) throw std::logic_error("weak case: '" + from + "' not in " + *field);
      field->replace(at, from.size(), to);
      v.push_back(c);
    }
  };
  weak("coulomb_friction", "-0.03", "-0.006");
  weak("quadratic_damping", "-0.3", "-0.035");
  weak("nonlinear_damping", "-0.3", "-0.03");
  weak("velocity_dependent_noise", "0.1", "0.002");
  weak("colored_noise", "\"intensity\": 0.04", "\"intensity\": 0.0003");
  weak("electromechanical_coupling", "\"coupling\": 0.5", "\"coupling\": 0.05");
  weak("harmonic_forcing", "0.08", "0.0045");
  return v;
}

/// The likelihood's name of the hidden effect's parameter (the oracle's z is taken of it).
inline std::string oracle_parameter(const HiddenCase& c) {
  const std::string& e = c.effect_name();
  if (e == "coulomb_friction") return "drift[sign(y)]";
  if (e == "quadratic_damping") return "drift[y*|y|]";
  if (e == "nonlinear_damping") return "drift[y^3]";
  if (e == "velocity_dependent_noise") return "diffusion[y^2]";
  if (e == "colored_noise") return "colored_noise.intensity";
  if (e == "electromechanical_coupling") return "electromechanical_coupling.coupling";
  if (e == "impact_stop") return "impact_stop.k_stop";
  if (e.rfind("harmonic_forcing", 0) == 0) return "harmonic_forcing.amplitude";
  return "";
}

/// The sensor-like sampling of the hidden cases: Taylor 1.5, 20 substeps per sample, a burn-in.
inline vehs::sim::SimulationOptions sampling_of(const HiddenCase& c, std::uint64_t seed) {
  vehs::sim::SimulationOptions o;
  o.dt = c.dt;
  o.substeps = 20;
  o.scheme = vehs::sim::Scheme::Taylor15;
  o.samples = c.samples;
  o.burn_in = 50.0;
  o.record_y = false;
  o.x0.lo = -1.0, o.x0.hi = 1.0;
  o.seed = vehs_test::seed(seed);
  o.records = c.records;
  return o;
}

/// The forcing's phase of every record of a hidden case with a phase per record (uniform on the circle).
inline std::vector<double> record_phases_of(const HiddenCase& c, std::uint64_t seed) {
  std::mt19937_64 rng(sampling_of(c, seed).seed);
  std::uniform_real_distribution<double> phase(0.0, 2.0 * M_PI);
  std::vector<double> v;
  for (int r = 0; r < c.records; ++r) v.push_back(phase(rng));
  return v;
}

inline vehs::Dataset hidden_data(const HiddenCase& c, std::uint64_t seed);

/// The case without its hidden effect: the baseline that generates its null data.
inline HiddenCase without_effect(HiddenCase c) {
  c.effect.clear();
  c.extra_drift.clear();
  c.extra_diffusion.clear();
  c.phase_per_record = false;
  return c;
}

/// The sd of a case's white sensor noise: its share of std(x) of a noise-free pilot of 4 records.
inline double sensor_noise_of(const HiddenCase& c, std::uint64_t seed) {
  if (!(c.sensor_noise_share > 0.0)) return 0.0;
  HiddenCase clean = c;
  clean.sensor_noise_share = 0.0;
  clean.records = 4;
  const vehs::Dataset pilot = hidden_data(clean, seed + 1000003);
  double m = 0.0, q = 0.0;
  for (double x : pilot.x) m += x, q += x * x;
  m /= double(pilot.x.size());
  return c.sensor_noise_share * std::sqrt(q / double(pilot.x.size()) - m * m);
}

/// The records of a hidden case: one simulation per record when the phase is random per record.
inline vehs::Dataset hidden_data(const HiddenCase& c, std::uint64_t seed) {
  vehs::sim::SimulationOptions o = sampling_of(c, seed);
  o.sensor_noise = sensor_noise_of(c, seed);
  if (!c.phase_per_record) return vehs::sim::simulate(truth_of(c), o);
  const std::vector<double> phases = record_phases_of(c, seed);
  vehs::Dataset all;
  o.records = 1;
  for (int r = 0; r < c.records; ++r) {
    o.first_record = std::uint64_t(r);
    all.append(vehs::sim::simulate(truth_of(c, phases[std::size_t(r)]), o));
  }
  return all;
}

/// identify's options for the baseline: the potential's terms, linear damping, constant noise.
inline vehs::identify::Options baseline_options_for(const HiddenCase& c) {
  vehs::identify::Options o;
  o.drift_library.clear();
  for (const auto& t : potential_library(c.potential)) o.drift_library.push_back(vehs::Term::parse(t));
  o.drift_library.push_back(vehs::Term::parse("y"));
  o.diffusion_library = {vehs::Term::parse("1")};
  o.sparsity = vehs::identify::Sparsity::None;
  return o;
}

}  // namespace score_test

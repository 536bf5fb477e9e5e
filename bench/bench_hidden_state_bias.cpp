// The moment fit's bias for a model with a hidden state, against the sampling interval (the
// evidence for the hidden-state rule of vehs/likelihood/adequacy.hpp).
//
//   bench_hidden_state_bias CASE RECORDS SEEDS [DT...]      (OMP_NUM_THREADS=1)
//   CASE: electromechanical_coupling (λ 0.8, coupling 0.5) or colored_noise (τ 0.6, intensity
//   0.04, 2D 0.01) on issue 13's bistable Duffing (β 0.1, 2D 0.04), records of 200 time units,
//   Taylor 1.5 at 20 substeps per sample after a burn-in of 50 (the data of the diagnose score
//   study's cases at Δt 0.05, seeds 100 + k). identify's moment fit with the effect given, and
//   with VEHS_HIDDEN_LIKELIHOOD=1 also the likelihood refinement of it (slow: ~75 s a seed at 288
//   records). Prints every seed and, per Δt, the mean of each parameter with its SE over seeds.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "vehs/identify/identify.hpp"
#include "vehs/io/model_file.hpp"
#include "vehs/likelihood/refine.hpp"
#include "vehs/sim/simulate.hpp"

using namespace vehs;

namespace {

struct Case {
  std::string truth_json;
  EffectId effect;
  std::map<std::string, double> truth;  ///< the parameters reported
};

Case case_of(const std::string& name) {
  if (name == "electromechanical_coupling")
    return {R"J({"drift": {"x": 1.0, "x^3": -1.0, "y": -0.1}, "diffusion": {"1": 0.04},
                "effects": [{"name": "electromechanical_coupling", "params": {"lambda": 0.8, "coupling": 0.5}}]})J",
            EffectId::ElectromechanicalCoupling,
            {{"lambda", 0.8}, {"coupling", 0.5}, {"beta", 0.1}}};
  if (name == "colored_noise")
    return {R"J({"drift": {"x": 1.0, "x^3": -1.0, "y": -0.1}, "diffusion": {"1": 0.01},
                "effects": [{"name": "colored_noise", "params": {"tau": 0.6, "intensity": 0.04}}]})J",
            EffectId::ColoredNoise,
            {{"tau", 0.6}, {"intensity", 0.04}, {"beta", 0.1}}};
  std::fprintf(stderr, "bench_hidden_state_bias: unknown case '%s'\n", name.c_str());
  std::exit(2);
}

Dataset data_of(const Case& c, int records, double dt, int seed) {
  sim::SimulationOptions o;
  o.dt = dt;
  o.substeps = 20;
  o.scheme = sim::Scheme::Taylor15;
  o.samples = static_cast<std::size_t>(std::lround(200.0 / dt));
  o.burn_in = 50.0;
  o.record_y = false;
  o.x0.lo = -1.0, o.x0.hi = 1.0;
  o.seed = static_cast<std::uint64_t>(100 + seed);
  o.records = records;
  return sim::simulate(model_from_json(nlohmann::json::parse(c.truth_json), "truth"), o);
}

/// The reported parameters of a fitted model: the effect's and β = −drift[y].
std::map<std::string, std::pair<double, double>> reported(const Model& m, EffectId id) {
  std::map<std::string, std::pair<double, double>> out;
  for (const Effect& e : m.effects)
    if (e.id == id)
      for (const auto& [k, v] : e.params) out[k] = {v, e.stderr_.count(k) ? e.stderr_.at(k) : NAN};
  out["beta"] = {-m.drift_coef("y"), m.drift_stderr.count("y") ? m.drift_stderr.at("y") : NAN};
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: bench_hidden_state_bias CASE RECORDS SEEDS [DT...]\n");
    return 2;
  }
  const Case c = case_of(argv[1]);
  const int records = std::atoi(argv[2]), seeds = std::atoi(argv[3]);
  std::vector<double> dts;
  for (int i = 4; i < argc; ++i) dts.push_back(std::atof(argv[i]));
  if (dts.empty()) dts = {0.1, 0.05, 0.025, 0.0125};
  const bool lik = std::getenv("VEHS_HIDDEN_LIKELIHOOD") && std::string(std::getenv("VEHS_HIDDEN_LIKELIHOOD")) == "1";
  identify::Options io;
  io.drift_library = {Term::parse("x"), Term::parse("x^3"), Term::parse("y")};
  io.diffusion_library = {Term::parse("1")};
  io.sparsity = identify::Sparsity::None;
  Effect e;
  e.id = c.effect;
  io.effects = {e};
  std::printf("# %s, %d records x 200 time units, seeds 100-%d; truth", argv[1], records, 99 + seeds);
  for (const auto& [k, v] : c.truth) std::printf(" %s %g", k.c_str(), v);
  std::printf("\n");
  for (const double dt : dts) {
    for (const char* fit : {"moments", "likelihood"}) {
      if (std::string(fit) == "likelihood" && !lik) continue;
      std::map<std::string, std::vector<double>> rel;
      for (int s = 0; s < seeds; ++s) {
        const Dataset d = data_of(c, records, dt, s);
        Model m = identify::identify(d, io).model;
        if (std::string(fit) == "likelihood") m = likelihood::refine({m, 0.0, {}}, d).model.model;
        std::printf("dt %.4g %-10s seed %3d", dt, fit, 100 + s);
        for (const auto& [k, vs] : reported(m, c.effect)) {
          std::printf("  %s %.4f ± %.4f", k.c_str(), vs.first, vs.second);
          if (c.truth.count(k)) rel[k].push_back(vs.first / c.truth.at(k) - 1.0);
        }
        std::printf("\n");
        std::fflush(stdout);
      }
      std::printf("dt %.4g %-10s mean relative error over %d seeds:", dt, fit, seeds);
      for (const auto& [k, v] : rel) {
        double m = 0.0, q = 0.0;
        for (double r : v) m += r;
        m /= double(v.size());
        for (double r : v) q += (r - m) * (r - m);
        const double se = v.size() > 1 ? std::sqrt(q / double(v.size() - 1) / double(v.size())) : NAN;
        std::printf("  %s %+.1f %% ± %.1f", k.c_str(), 100 * m, 100 * se);
      }
      std::printf("\n");
    }
  }
  return 0;
}

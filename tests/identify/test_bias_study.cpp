// Bias studies over many seeds (hidden: run by hand, not in CI). Each study repeats one of the
// suite's identification tests on N independent data sets (seeds 1..N, env NSEEDS, default 50)
// and prints, for every true drift / diffusion term and fitted effect parameter, the mean of
// z = (estimate − truth)/SE with its standard error sd(z)/√N, the spread sd(z) (≈ 1 when the
// standard errors are calibrated) and the mean relative error with its standard error. A term
// is biased at the tests' resolution when its mean z is several of its standard errors off 0.
//
//   build/tests/test_identify "[.bias]" -s          (all studies, ≈ 25 min on 2 cores)
//   build/tests/test_identify "[.bias][coulomb]"    (one study; env NSEEDS=N, SUBSTEPS=S,
//                                                    CONTROL=0|1 (effect only | control only),
//                                                    POT=bistable|monostable for [impact])
//
// The studies and their controls (what the figures in the comments of the tests rest on):
//  * coulomb: the "Coulomb friction as an effect" test (paper model + μ sign(y), μ = 0.05,
//    20 records × 10⁵ samples at Δt = 0.005 of a continuous process) and its control without
//    friction (μ = 0, sign(y) still in the dictionary);
//  * impact: the "impact stops (stiffness and both gaps) on two potentials" test with the
//    test's own random draw of k_stop and the gaps per seed, and the control without stops.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <random>
#include <sstream>
#include <vector>

#include "identify_fixtures.hpp"

using namespace vehs;
using namespace vehs_test;

namespace {

int env_int(const char* name, int fallback) {
  const char* v = std::getenv(name);
  return v ? std::atoi(v) : fallback;
}

/// z and relative errors of every quantity over the seeds of one study.
class Tally {
 public:
  void add(const std::string& what, double estimate, double truth, double se) {
    auto& s = rows_[what];
    s.z.push_back((estimate - truth) / se);
    s.rel.push_back((estimate - truth) / std::abs(truth));
  }
  void print(const std::string& title) const {
    std::cout << "\n== " << title << "\n"
              << std::left << std::setw(24) << "quantity" << std::right << std::setw(6) << "n"
              << std::setw(18) << "mean z +- se" << std::setw(8) << "sd z" << std::setw(9) << "max|z|"
              << std::setw(24) << "mean rel.err +- se" << "\n";
    for (const auto& [what, s] : rows_) {
      const auto [mz, sz] = mean_sd(s.z);
      const auto [mr, sr] = mean_sd(s.rel);
      double mx = 0.0;
      for (double z : s.z) mx = std::max(mx, std::abs(z));
      const double n = static_cast<double>(s.z.size());
      std::cout << std::left << std::setw(24) << what << std::right << std::setw(6) << s.z.size()
                << std::fixed << std::setprecision(2) << std::setw(9) << mz << " +- " << std::setw(5)
                << sz / std::sqrt(n) << std::setw(8) << sz << std::setw(9) << mx << std::setprecision(3)
                << std::setw(11) << 100 * mr << "% +- " << std::setw(6) << 100 * sr / std::sqrt(n) << "%"
                << std::defaultfloat << "\n";
    }
    std::cout << std::flush;
  }

 private:
  struct Series {
    std::vector<double> z, rel;
  };
  static std::pair<double, double> mean_sd(const std::vector<double>& v) {
    double m = 0.0, s = 0.0;
    for (double x : v) m += x;
    m /= static_cast<double>(v.size());
    for (double x : v) s += (x - m) * (x - m);
    return {m, v.size() > 1 ? std::sqrt(s / static_cast<double>(v.size() - 1)) : 0.0};
  }
  std::map<std::string, Series> rows_;
};

void tally_model(Tally& t, const Model& learned, const Model& truth) {
  for (const auto& tc : truth.drift)
    t.add("drift " + tc.term.name(), learned.drift_coef(tc.term.name()), tc.coef,
          learned.drift_stderr.at(tc.term.name()));
  for (const auto& tc : truth.diffusion)
    t.add("diffusion " + tc.term.name(), learned.diffusion_coef(tc.term.name()), tc.coef,
          learned.diffusion_stderr.at(tc.term.name()));
}

/// The Coulomb friction test's data and fit at seed `seed` (μ = 0: the control).
void coulomb_study(double mu, int substeps) {
  const int n = env_int("NSEEDS", 50);
  Tally t;
  for (int s = 1; s <= n; ++s) {
    Model truth = paper_truth();
    if (mu > 0) {
      truth.drift.push_back({Term::sign_y(), -mu});
      canonicalize(truth.drift, "truth");
    }
    const Dataset d = simulate(truth, 0.005, substeps, 20, 100000, 5000 + static_cast<std::uint64_t>(s));
    identify::Options o;
    o.effects.push_back(effect_from_json("coulomb_friction", "test", false));
    const auto r = identify::identify(d, o);
    tally_model(t, r.model, truth);
    const auto j = model_to_json(r.model);
    if (mu > 0)
      t.add("mu", j["effect_params"][0]["params"]["mu"].get<double>(), mu,
            j["effect_params"][0]["stderr"]["mu"].get<double>());
  }
  std::ostringstream title;
  title << "coulomb: paper model, mu = " << mu << ", dt 0.005, " << substeps << " substeps, " << n << " seeds";
  t.print(title.str());
}

/// The impact-stop test's draw (k_stop, gaps at a quantile of |x|) and fit, seeds 1..N.
void impact_study(const std::string& pot, bool stops, int substeps) {
  const int n = env_int("NSEEDS", 50);
  Tally t;
  for (int s = 1; s <= n; ++s) {
    std::mt19937_64 g(static_cast<std::uint64_t>(1000 * s + (pot == "bistable" ? 1 : 2)));
    Model truth = hidden_effect_potential(pot);
    const Effect e = draw_impact_stop(truth, g);
    if (stops) truth.effects = {e};
    sim::SimulationOptions so;
    so.dt = 0.01;
    so.substeps = substeps;
    so.records = 8;
    so.samples = 40000;
    so.seed = 200 + g() % 1000 + 100000 * static_cast<std::uint64_t>(s);
    so.scheme = sim::Scheme::Taylor15;
    so.burn_in = 20.0;
    so.record_y = false;
    const Dataset d = sim::simulate(truth, so);
    identify::Options o;
    o.drift_library = {Term::parse("x"), Term::parse("x^2"), Term::parse("x^3"), Term::parse("y")};
    o.diffusion_library = paper_diffusion_library(2);
    if (stops) {
      Effect req;
      req.id = EffectId::ImpactStop;
      o.effects = {req};
    }
    const identify::Result r = identify::identify(d, o);
    if (stops) {
      const Effect& f = r.model.effects.at(0);
      for (const char* k : {"k_stop", "gap", "gap_neg"}) t.add(k, f.param(k), e.param(k), f.stderr_.at(k));
    }
    truth.effects.clear();
    tally_model(t, r.model, truth);
  }
  std::ostringstream title;
  title << "impact: " << pot << (stops ? " with stops" : " without stops (control)") << ", dt 0.01, "
        << substeps << " substeps, " << n << " seeds";
  t.print(title.str());
}

}  // namespace

TEST_CASE("bias study: diffusion with Coulomb friction (sign(y) in the drift) over seeds", "[.bias][coulomb]") {
  const int substeps = env_int("SUBSTEPS", 20);
  const int which = env_int("CONTROL", 2);  // 0: friction only, 1: control only, 2: both
  if (which != 1) coulomb_study(0.05, substeps);
  if (which != 0) coulomb_study(0.0, substeps);
}

TEST_CASE("bias study: diffusion with impact stops (a kink in x) over seeds", "[.bias][impact]") {
  const int substeps = env_int("SUBSTEPS", 10);
  const int which = env_int("CONTROL", 2);  // 0: stops only, 1: control only, 2: both
  const char* only = std::getenv("POT");    // bistable or monostable (default both)
  for (const char* pot : {"bistable", "monostable"}) {
    if (only && std::string(only) != pot) continue;
    if (which != 1) impact_study(pot, true, substeps);
    if (which != 0) impact_study(pot, false, substeps);
  }
}

// The likelihood's score-test suspects (vehs/diagnose/score_suspects.hpp): data with an effect
// hidden, simulated as a sensor samples a continuous process (Taylor 1.5 with 20 substeps per
// sample, a burn-in from the stationary regime), 25–40 records, bi-, tri- and penta-stable
// potentials, parameters of issue 13's table (μ = 0.03, c = 0.3, τ = 0.6, forcing with a random
// phase per record, …) that the code under test never sees. The baseline is the potential's own
// terms fitted by identify.
#include <catch2/catch.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

#include "vehs/core/model.hpp"
#include "vehs/diagnose/distributions.hpp"
#include "vehs/diagnose/score_suspects.hpp"
#include "vehs/identify/identify.hpp"
#include "vehs/io/model_file.hpp"
#include "vehs/sim/simulate.hpp"

#include "diagnose_fixtures.hpp"
#include "score_fixtures.hpp"

using namespace vehs;
using namespace vehs_test;
using namespace score_test;

namespace {

std::string describe(const diagnose::ScoreSuspectReport& r) {
  std::string s = r.note;
  for (const auto& sp : r.ranked) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "\n   %s: stat %.3g p %.3g z %.2f power %.2f (%.1f s)", sp.effect.c_str(),
                  sp.statistic, sp.p_value, sp.z, sp.power, sp.seconds);
    s += buf;
    for (const auto& [k, v] : sp.params) {
      auto it = sp.params_stderr.find(k);
      s += " " + k + "=" + std::to_string(v) + (it != sp.params_stderr.end() ? "±" + std::to_string(it->second) : "");
    }
  }
  for (const auto& [e, why] : r.untested) s += " | untested " + e + ": " + why;
  return s;
}

}  // namespace

TEST_CASE("score suspects: explore (prints the table for every hidden effect)", "[.score_explore]") {
  const char* which = std::getenv("VEHS_SCORE_CASE");
  const std::string only = which ? which : "";
  for (const HiddenCase& hc : hidden_cases()) {
    if (!only.empty() && hc.name != only) continue;
    for (int s = 0; s < (std::getenv("VEHS_SCORE_SEEDS") ? std::atoi(std::getenv("VEHS_SCORE_SEEDS")) : 1); ++s) {
      const Dataset d = hidden_data(hc, 100 + s);
      const Model base = identify::identify(d, baseline_options_for(hc)).model;
      diagnose::ScoreSuspectOptions o;
      const auto t0 = std::chrono::steady_clock::now();
      const auto rep = diagnose::score_suspects(base, d, 0.0, o);
      const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::printf("%s seed %d (%.1f s): %s\n", hc.name.c_str(), s, sec, describe(rep).c_str());
    }
  }
}

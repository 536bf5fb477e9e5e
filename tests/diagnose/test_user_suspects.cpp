// A user's own effect as a suspect (vehs/core/user_effect.hpp; diagnose's Options::user_effects):
// friction that differs by direction hidden in bistable records (continuous-time records sampled
// as a sensor would, score_fixtures.hpp), the user's definition on top of the baseline's linear
// damping — Coulomb friction per direction and the extra damping when moving backward. The
// baseline is the potential's terms and y fitted by identify.
#include <catch2/catch.hpp>

#include <string>

#include "vehs/diagnose/diagnose.hpp"
#include "vehs/diagnose/score_suspects.hpp"

#include "diagnose_fixtures.hpp"
#include "score_fixtures.hpp"
#include "score_runs.hpp"

using namespace vehs;
using namespace score_test;

namespace {

UserEffect directional_effect() {
  UserEffect e;
  e.name = "directional_friction";
  e.params = {{"Fp", Term::parse("-(y>0)"), false}, {"Fm", Term::parse("(y<0)"), false}, {"dc", Term::parse("-y*(y<0)"), false}};
  return e;
}

/// The bistable records of the score tests at their CI size, with the directional friction
/// hidden (Fp 0.08, Fm 0.02, dc 0.3) or not.
HiddenCase directional_case(bool hidden) {
  HiddenCase c = case_named("none");
  c.records = 16;
  c.samples = 2500;
  if (hidden) c.extra_drift = R"J("(y>0)": -0.08, "(y<0)": 0.02, "y*(y<0)": -0.3)J";
  return c;
}

}  // namespace

// Named first and significant where it is hidden: measured z-equivalent of the user's χ²₃ test
// 14.6 (seed 21), runner-up coulomb_friction 6.7 (its sign(y) is the mean of the two Coulomb
// terms); a claim needs z ≈ 3.3, so a miss is ≥ 11 SD away, and the runner-up overtakes only by
// a shift of ≥ 7.9 in the difference (SD ≈ √2: P ≤ 1e-8). On records without it (seed 11) no
// claim: its p must exceed 0.01/300 (false failure ≤ 3.3e-5 for a calibrated χ²₃ test).
TEST_CASE("user suspects: a user's effect is tested as the catalogue's are", "[diagnose][user]") {
  diagnose::ScoreSuspectOptions options;
  options.user_effects = {directional_effect()};
  {
    const HiddenCase hc = directional_case(true);
    const Outcome o = run_case(hc, hidden_data(hc, 21), options);
    INFO("hidden (" << o.seconds << " s):" << describe(o.report));
    REQUIRE_FALSE(o.report.ranked.empty());
    const auto& first = o.report.ranked.front();
    CHECK(first.effect == "directional_friction");
    CHECK(first.significant);
    CHECK(first.dof == 3.0);
    CHECK(first.params.count("dc") == 1);
    CHECK(first.add.empty());  // the tools write the user's definition
  }
  {
    const HiddenCase hc = directional_case(false);
    const Outcome o = run_case(hc, hidden_data(hc, 11), options);
    INFO("control (" << o.seconds << " s):" << describe(o.report));
    bool tested = false;
    for (const auto& s : o.report.ranked)
      if (s.effect == "directional_friction") {
        tested = true;
        CHECK(s.p_value > 0.01 / 300.0);
      }
    CHECK(tested);
  }
}

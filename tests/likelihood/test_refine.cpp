// Maximum likelihood with selection on the bistable Duffing of issue 12 (U = −x²/2 + x⁴/4,
// β = 0.1, 2D = 0.04), simulated from continuous time (40 internal steps per sample) and
// sampled at ω·Δt ≈ 0.5 and 1.0 (Δt = 0.35, 0.7; ω = √2 in the wells), without and with white
// sensor noise of 2 % of std(x) — the cases where the moment estimators fail (issue 12).
// The start is the truth perturbed by 20 % plus spurious terms (x², x²·y, 2Q·x²) and a
// measurement noise that the selection must drop or keep.
#include <catch2/catch.hpp>

#include <algorithm>

#include "likelihood_fixtures.hpp"
#include "vehs/likelihood/refine.hpp"

using namespace vehs;
using namespace vehs_lik_test;

namespace {

likelihood::ObservedModel perturbed_start(const Model& truth, double noise_start) {
  likelihood::ObservedModel s{truth, noise_start, {}};
  for (auto& tc : s.model.drift) tc.coef *= 1.2;
  for (auto& tc : s.model.diffusion) tc.coef *= 0.8;
  s.model.drift.push_back({Term::parse("x^2"), 0.02});
  s.model.drift.push_back({Term::parse("x^2*y"), -0.02});
  s.model.diffusion.push_back({Term::parse("x^2"), 0.002});
  canonicalize(s.model.drift, "start");
  canonicalize(s.model.diffusion, "start");
  return s;
}

}  // namespace

// False-failure probability per run ≤ 1e-4: four data sets, each ≤ 2.5e-5 = support (three or
// four spurious candidates, each kept with probability ≤ α = 2e-6 by the LR test; true terms
// have |z| > 20) + parameters (five or fewer, each outside z_bound(5, 1.5e-5) ≈ 4.8 SE with
// probability 3e-6 when the estimator is unbiased and normal).
TEST_CASE("bistable Duffing at ω·Δt 0.5 and 1.0, with and without sensor noise: exact support, "
          "parameters within their standard errors", "[likelihood][refine][slow]") {
  const double dt = GENERATE(0.35, 0.7);
  const bool noisy = GENERATE(false, true);
  const Model truth = bistable();
  const std::uint64_t seed = 100 + std::uint64_t(dt * 100) + (noisy ? 1 : 0);
  const double sd = sd_of(simulate(truth, dt, 8, 1500.0, seed).x);
  const double noise = noisy ? 0.02 * sd : 0.0;
  const Dataset d = simulate(truth, dt, 8, 1500.0, seed, noise);
  likelihood::RefineOptions o;
  o.select = true;
  o.criterion = likelihood::SelectionCriterion::LikelihoodRatio;
  o.lr_alpha = 2e-6;
  const likelihood::Result r = likelihood::refine(perturbed_start(truth, 0.01 * sd), d, o);
  INFO("dt " << dt << ", noise " << noise << "\n" << r.summary.FullReport());
  std::vector<std::string> expected = {"diffusion[1]", "drift[x]", "drift[x^3]", "drift[y]"};
  if (noisy) expected.push_back("measurement_sd");
  std::sort(expected.begin(), expected.end());
  CHECK(support(r) == expected);
  std::map<std::string, double> want = {{"drift[x]", 1.0}, {"drift[x^3]", -1.0}, {"drift[y]", -0.1},
                                        {"diffusion[1]", 0.04}};
  if (noisy) want["measurement_sd"] = noise;
  const Check c = against(r, want);
  CHECK(c.max_z <= z_bound(5, 1.5e-5));
  CHECK(r.summary.converged);
  // the selection's shortcuts (refine.hpp): a block removal passed its joint 2ΔlogL against the
  // single threshold; a removal decided without a refit had z² beyond kWaldKeepFactor × threshold
  for (const auto& st : r.summary.selection) {
    INFO(st.removed << st.added);
    if (st.together > 1) CHECK((st.accepted && st.delta < st.threshold && st.z < 2.0));
    if (st.by_wald) CHECK((!st.accepted && st.z * st.z > likelihood::kWaldKeepFactor * st.threshold));
  }
}

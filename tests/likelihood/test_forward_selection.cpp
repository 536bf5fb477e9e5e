// Forward steps of the likelihood's selection (vehs/likelihood/refine.hpp: candidate_drift;
// src/likelihood/forward_selection.cpp) and the restart of a start whose filter diverges
// (refine.cpp: repair_start). The bistable Duffing of issue 12 (β 0.1, 2D 0.04) at ω·Δt ≈ 0.5.
// A second outside tester: 5 % sensor noise made the moment fit drop the damping y, which the
// likelihood then only pruned; and moment fits with x⁵ … x¹⁰ in place of x³ made the filter
// diverge at the start values, an error on legitimate data.
#include <catch2/catch.hpp>

#include <algorithm>

#include "likelihood_fixtures.hpp"
#include "vehs/core/diffusion_domain.hpp"
#include "vehs/likelihood/refine.hpp"

using namespace vehs;
using namespace vehs_lik_test;

namespace {

likelihood::RefineOptions forward_options() {
  likelihood::RefineOptions o;
  o.select = true;
  o.criterion = likelihood::SelectionCriterion::LikelihoodRatio;
  o.lr_alpha = 2e-6;
  o.estimate_measurement_noise = false;
  for (const char* t : {"x", "x^2", "x^3", "y", "x*y", "x^2*y"}) o.candidate_drift.push_back(Term::parse(t));
  for (const char* t : {"1", "x^2"}) o.candidate_diffusion.push_back(Term::parse(t));
  return o;
}

const std::vector<std::string> kTrueSupport = {"diffusion[1]", "drift[x]", "drift[x^3]", "drift[y]"};
const std::map<std::string, double> kTruth = {
    {"drift[x]", 1.0}, {"drift[x^3]", -1.0}, {"drift[y]", -0.1}, {"diffusion[1]", 0.04}};

}  // namespace

// False-failure probability per run ≤ 1e-4: two data sets, each ≤ 5e-5 = support (eight
// candidate terms, each added with probability ≤ α = 2e-6 by the LR test; the true terms have
// |z| > 10) + four parameters outside z_bound(4, 1e-5).
TEST_CASE("a start without the damping: the forward step adds y by its score test", "[likelihood][selection]") {
  const Model truth = bistable();
  const Dataset d = simulate(truth, 0.35, 8, 1500.0, 611);
  likelihood::ObservedModel start{truth, 0.0, {}};
  start.model.drift.erase(std::remove_if(start.model.drift.begin(), start.model.drift.end(),
                                         [](const TermCoef& tc) { return tc.term == Term::parse("y"); }),
                          start.model.drift.end());
  const likelihood::Result r = likelihood::refine(start, d, forward_options());
  INFO(r.summary.FullReport());
  CHECK(support(r) == kTrueSupport);
  const bool added_y = std::any_of(r.summary.selection.begin(), r.summary.selection.end(),
                                   [](const likelihood::SelectionStep& s) { return s.added == "drift[y]" && s.accepted; });
  CHECK(added_y);
  CHECK(against(r, kTruth).max_z <= z_bound(4, 1e-5));
}

TEST_CASE("a start whose filter diverges (x^5 > 0): restarted without terms of degree > 3",
          "[likelihood][selection]") {
  const Model truth = bistable();
  const Dataset d = simulate(truth, 0.35, 8, 1500.0, 612);
  likelihood::ObservedModel start{truth, 0.0, {}};
  start.model.drift.push_back({Term::parse("x^5"), 0.5});
  canonicalize(start.model.drift, "start");
  likelihood::RefineOptions o = forward_options();
  o.select = false;
  CHECK_THROWS_WITH(likelihood::log_likelihood(start, d, o.filter), Catch::Contains("diverged"));
  o.select = true;
  const likelihood::Result r = likelihood::refine(start, d, o);
  INFO(r.summary.FullReport());
  CHECK(support(r) == kTrueSupport);
  CHECK(against(r, kTruth).max_z <= z_bound(4, 1e-5));
}

// A nonlinear damping x²·y (c = −0.2) that the start lacks, on 34 000 samples screened on a share
// of 0.12: the screen's scores stay below z 3 (this seed), so before, nothing was added; its
// full-data score is z 12.4 (2ΔlogL 153 against the bar 22.6). False-failure probability per run
// ≤ 1e-4: the step needs the full-data z above 4.75, 7.6 sd below its value here; the other
// candidates are each added with probability ≤ α = 2e-6; five parameters outside z_bound(5, 1e-5).
TEST_CASE("a weak term that the screened share cannot decide is tested on all the data",
          "[likelihood][selection][screen]") {
  const double c = -0.2;
  Model truth = bistable();
  truth.drift.push_back({Term::parse("x^2*y"), c});
  canonicalize(truth.drift, "truth");
  const Dataset d = simulate(truth, 0.35, 8, 1500.0, 613);
  likelihood::ObservedModel start{bistable(), 0.0, {}};
  likelihood::RefineOptions o = forward_options();
  o.screen_samples = 4000;  // a share of 0.12 of the 34 000 samples
  std::vector<std::string> log;
  o.log = [&](const std::string& line) { log.push_back(line); };
  const likelihood::Result r = likelihood::refine(start, d, o);
  std::string text;
  for (const auto& l : log) text += l + "\n";
  INFO(text << r.summary.FullReport());
  CHECK(text.find("tested on all 34280 samples") != std::string::npos);
  CHECK(support(r) == std::vector<std::string>{"diffusion[1]", "drift[x]", "drift[x^2*y]", "drift[x^3]", "drift[y]"});
  std::map<std::string, double> truth_values = kTruth;
  truth_values["drift[x^2*y]"] = c;
  CHECK(against(r, truth_values).max_z <= z_bound(5, 1e-5));
}

// A diffusion 0.04 + 0.03·x + 0.02·x² (positive everywhere) on a start with a constant diffusion:
// x alone would make a22(x, 0) = 2D + c·x negative for large |x|, a model no tool simulates (a
// positioning-rig study got 2D + 0.00106·x, refused by diagnose's twins), so the forward step may
// add x only once x² leads. Here x alone (the larger score, |z| ≈ 64) also fails the filter
// within the data, which used to end the forward steps with neither term. Both terms' |z| are
// above 29 against a bar of 4.75 (false-failure probability far below 1e-4).
TEST_CASE("the forward step adds no odd leading diffusion power", "[likelihood][selection]") {
  Model truth = bistable();
  truth.diffusion = {{Term::parse("1"), 0.04}, {Term::parse("x"), 0.03}, {Term::parse("x^2"), 0.02}};
  const Dataset d = simulate(truth, 0.35, 8, 1500.0, 613);
  likelihood::ObservedModel start{bistable(), 0.0, {}};
  likelihood::RefineOptions o = forward_options();
  o.candidate_diffusion = {Term::parse("x"), Term::parse("x^2"), Term::parse("x^3")};
  const likelihood::Result r = likelihood::refine(start, d, o);
  INFO(r.summary.FullReport());
  bool x2_in = false, x_in = false;
  for (const likelihood::SelectionStep& s : r.summary.selection) {
    if (!s.accepted || s.added.empty()) continue;
    if (s.added == "diffusion[x^2]") x2_in = true;
    CHECK(s.added != "diffusion[x^3]");
    if (s.added == "diffusion[x]") {
      CHECK(x2_in);
      x_in = true;
    }
  }
  CHECK(x2_in);
  CHECK(x_in);
  CHECK(diffusion_negative_at_large_x(r.model.model).empty());
}

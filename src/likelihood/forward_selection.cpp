// Forward steps of refine()'s selection (vehs/likelihood/refine.hpp: candidate_drift): the
// score test of every candidate term at the current fit, in one derivative pass.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "vehs/core/diffusion_domain.hpp"
#include "vehs/core/error.hpp"
#include "vehs/likelihood/detail/data_share.hpp"
#include "vehs/likelihood/detail/selection.hpp"
#include "vehs/likelihood/score_test.hpp"

namespace vehs::likelihood::detail {

namespace {

/// Score tests on at most RefineOptions::screen_samples samples: the pass differentiates in every
/// candidate at once (12 candidates on 10⁶ samples: 14 s, more than the first fit). A candidate
/// that passes the screen is decided by the refit's 2ΔlogL on all the data.
/// The screen's bar on a share f of the data: a term at the full-data bar has z² ≈ f·bar there;
/// never below z = 3 (a spurious pass costs one refit, with probability 0.27 % per candidate).
double screen_bar(double bar, double share) { return share < 1.0 ? std::max(bar * share, 9.0) : bar; }
/// Leading candidates confirmed on all the data when the share cannot decide them.
constexpr std::size_t kConfirmed = 3;

struct Candidate {
  Term term;
  bool drift = true;
  std::string name() const { return std::string(drift ? "drift[" : "diffusion[") + term.name() + "]"; }
};

bool has_term(const TermList& list, const Term& t) {
  return std::any_of(list.begin(), list.end(), [&](const TermCoef& tc) { return tc.term == t && tc.coef != 0.0; });
}

/// The highest power of x among the y-free monomials of the diffusion (-1: none).
int leading_x_power(const TermList& diffusion) {
  int p = -1;
  for (const TermCoef& tc : diffusion)
    if (tc.coef != 0.0 && tc.term.is_polynomial() && tc.term.py == 0) p = std::max(p, tc.term.px);
  return p;
}

/// Every candidate term the model lacks, except a y-free diffusion monomial of an odd power above
/// the diffusion's leading one: a22(x, 0) would then turn negative for large |x| whatever its
/// sign (vehs/core/diffusion_domain.hpp), a model no tool can simulate.
std::vector<Candidate> candidates(const Model& m, const RefineOptions& o) {
  std::vector<Candidate> c;
  for (const Term& t : o.candidate_drift)
    if (!has_term(m.drift, t)) c.push_back({t, true});
  const int lead = leading_x_power(m.diffusion);
  for (const Term& t : o.candidate_diffusion) {
    const bool odd_lead = t.is_polynomial() && t.py == 0 && t.px > lead && t.px % 2 == 1;
    if (!has_term(m.diffusion, t) && !odd_lead) c.push_back({t, false});
  }
  return c;
}

/// `m` with the candidate's coefficient set to `value` (canonical order kept).
ObservedModel with_term(ObservedModel m, const Candidate& c, double value) {
  TermList& list = c.drift ? m.model.drift : m.model.diffusion;
  list.erase(std::remove_if(list.begin(), list.end(), [&](const TermCoef& tc) { return tc.term == c.term; }), list.end());
  list.push_back({c.term, value});
  canonicalize(list, "likelihood forward step");
  return m;
}

double threshold(const RefineOptions& o, double n) {
  return o.criterion == SelectionCriterion::Bic ? std::log(n) : chi2_1_upper_quantile(o.lr_alpha);
}

void log_step(const RefineOptions& o, const SelectionStep& st) {
  if (!o.log) return;
  char line[256];
  std::snprintf(line, sizeof line, "likelihood selection: add %s (score |z| %.3g): 2 dlogL %.4g vs %.4g: %s",
                st.added.c_str(), st.z, st.delta, st.threshold, st.accepted ? "added" : "not added");
  o.log(line);
}

/// The score tests of every candidate, each in its own group, at `current` on `data`.
std::vector<ScoreTestResult> candidate_tests(const ObservedModel& current, const std::vector<Candidate>& cand,
                                             const Dataset& data, const ScoreTestOptions& so) {
  ObservedModel probe = current;
  std::vector<std::vector<std::string>> groups;
  for (const Candidate& c : cand) probe = with_term(std::move(probe), c, 1e-300), groups.push_back({c.name()});
  return score_tests(probe, data, groups, so);
}

/// When the screen passes no candidate, its leading ones (at most kConfirmed, largest z first)
/// are tested again on all the data and their results replace the screen's (true): the share
/// cannot decide a term below its bar of z 3 — a term at full-data z 5 on 10⁶ samples shows
/// z ≈ 2.2 on the 2·10⁵ screened, and on a share of 0.12 a nonlinear damping x²·y at full-data
/// z 12.4 showed z < 3 (tests/likelihood/test_forward_selection.cpp): both were never added.
/// The cost is one pass over all the data in kConfirmed candidates when the forward steps end.
bool confirm_undecided(const ObservedModel& current, std::vector<Candidate>& cand, std::vector<ScoreTestResult>& tests,
                       const Dataset& data, const ScoreTestOptions& so, double bar, double share,
                       const RefineOptions& o) {
  std::vector<std::size_t> order(tests.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return std::abs(tests[a].z) > std::abs(tests[b].z); });
  if (order.empty() || tests[order[0]].z * tests[order[0]].z > screen_bar(bar, share)) return false;  // the screen decides
  std::vector<Candidate> lead;
  for (std::size_t i = 0; i < order.size() && i < kConfirmed; ++i) lead.push_back(cand[order[i]]);
  const std::vector<ScoreTestResult> full = candidate_tests(current, lead, data, so);
  if (o.log) {
    char line[200];
    std::snprintf(line, sizeof line, "likelihood selection: nothing passed the screened share; its leading %zu candidate(s) tested on all %zu samples",
                  lead.size(), full.empty() ? std::size_t(0) : full[0].observations);
    o.log(line);
  }
  cand = std::move(lead);
  tests = full;
  return true;
}

}  // namespace

Result add_terms(Result current, const Dataset& data, const RefineOptions& o, const FitChoice& choice,
                 std::vector<SelectionStep>& steps) {
  const double bar = threshold(o, double(current.summary.observations));
  const double share = std::min(1.0, o.screen_samples / double(std::max<std::size_t>(current.summary.observations, 1)));
  const Dataset sub = share < 1.0 ? warm_start_share(data, share, choice.per_record_phase) : Dataset{};
  const Dataset& screen = share < 1.0 ? sub : data;
  ScoreTestOptions so;
  so.filter = o.filter;
  so.estimate_measurement_noise = choice.fit_measurement_noise;
  so.fixed = choice.fixed;
  for (int added = 0; added < o.max_added; ++added) {
    std::vector<Candidate> cand = candidates(current.model.model, o);
    if (cand.empty()) break;
    std::vector<ScoreTestResult> tests;
    bool on_all = share >= 1.0;
    const auto t0 = std::chrono::steady_clock::now();
    try {
      tests = candidate_tests(current.model, cand, screen, so);
      if (!on_all) on_all = confirm_undecided(current.model, cand, tests, data, so, bar, share, o);
    } catch (const Error& e) {
      if (o.log) o.log(std::string("likelihood selection: no forward step (") + e.what() + ")");
      break;
    }
    std::size_t best = 0;
    for (std::size_t i = 1; i < tests.size(); ++i)
      if (std::abs(tests[i].z) > std::abs(tests[best].z)) best = i;
    SelectionStep st;
    st.added = cand[best].name();
    st.z = std::abs(tests[best].z);
    st.threshold = bar;
    if (!(st.z * st.z > (on_all ? bar : screen_bar(bar, share))) || tests[best].estimate.empty() ||
        !std::isfinite(tests[best].estimate[0])) {
      if (o.log) {
        char line[240];
        std::snprintf(line, sizeof line, "likelihood selection: nothing to add (largest score |z| %.3g, %s; bar %.3g on %zu samples; %zu score tests in %.3g s)",
                      st.z, st.added.c_str(), std::sqrt(on_all ? bar : screen_bar(bar, share)), tests[best].observations, tests.size(),
                      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        o.log(line);
      }
      break;
    }
    Result r;
    try {
      r = fit_support(with_term(current.model, cand[best], tests[best].estimate[0]), data, o, choice, false);
    } catch (const Error& e) {
      if (o.log) o.log("likelihood selection: cannot add " + st.added + " (" + e.what() + ")");
      break;
    }
    st.log_likelihood = r.log_likelihood;
    st.delta = 2.0 * (r.log_likelihood - current.log_likelihood);
    st.accepted = st.delta > bar;
    if (const std::string why = diffusion_negative_at_large_x(r.model.model); st.accepted && !why.empty()) {
      if (o.log) o.log("likelihood selection: not adding " + st.added + ": the fitted " + why);
      break;
    }
    log_step(o, st);
    steps.push_back(st);
    if (!st.accepted) break;
    current = std::move(r);
  }
  return current;
}

}  // namespace vehs::likelihood::detail

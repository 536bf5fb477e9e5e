// What a diagnosis concludes (diagnose.hpp: Result::recommended, outside_catalogue,
// conclusion): the suspects confirmed by held-out refits (confirmation.hpp), or — when none is —
// that the misfit is outside the catalogue, with what fails and what the innovations show.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "comparison.hpp"
#include "unit_math.hpp"

namespace vehs::diagnose::detail {

namespace {

std::string join(const std::vector<std::string>& v, const std::string& sep) {
  std::string s;
  for (const auto& a : v) s += (s.empty() ? "" : sep) + a;
  return s;
}

/// The effects behind the significant suspects: score tests first (by p), then held-out ones.
std::vector<Candidate> significant_suspects(const Result& res) {
  std::vector<Candidate> out;
  // a forcing with one phase per record is refitted so only when it is the more significant form
  auto add = [&](const std::string& name, const std::string& evidence, double all_data_z) {
    const bool per_record = name == "harmonic_forcing_per_record";
    Candidate cand{EffectId{}, evidence, per_record, all_data_z};
    if (const UserEffect* u = find_user_effect(res.user_effects, name)) cand.user = *u;
    else cand.id = enum_from_string(kEffectNames, per_record ? "harmonic_forcing" : name, "suspect");
    for (Candidate& c : out)
      if (c.name() == cand.name()) {
        c.evidence += "; " + evidence;
        return;
      }
    out.push_back(std::move(cand));
  };
  const double none = std::numeric_limits<double>::quiet_NaN();
  for (const auto& s : res.score_suspects.ranked)
    if (s.significant)
      add(s.effect, (s.effect == "harmonic_forcing_per_record" ? "score test (one phase per record) z = " : "score test z = ") + fmt(s.z),
          s.z);
  for (const auto& s : res.suspects.ranked)
    if (s.significant) add(s.effect, "held-out z = " + fmt(s.z), none);
  return out;
}

/// " — not resolved by these data from quadratic_damping" for a member of an unresolved
/// look-alike group of the score tests (score_suspects.hpp), else "".
std::string unresolved_from(const Result& res, const std::string& effect) {
  for (const auto& s : res.score_suspects.ranked)
    if (s.effect == effect && !s.not_resolved_from.empty())
      return " — not resolved by these data from " + join(s.not_resolved_from, ", ");
  return "";
}

/// "one_step, drift_shape and residual_spectrum fail (smallest p 1e-52)".
std::string failing_components(const Result& res) {
  std::string names;
  double p_min = 1.0;
  int n = 0;
  for (const auto& c : res.components)
    if (c.test.available && c.test.p_value < res.threshold) {
      names += (names.empty() ? "" : ", ") + c.name;
      p_min = std::min(p_min, c.test.p_value);
      ++n;
    }
  if (n == 0) return "no component fails";
  return names + (n == 1 ? " fails" : " fail") + " (smallest p " + (p_min > 0 ? fmt(p_min, 2) : std::string("< 1e-300")) + ")";
}

double smallest_p(const Result& res) {
  double p = 1.0;
  for (const auto& c : res.components)
    if (c.test.available) p = std::min(p, c.test.p_value);
  return p;
}

/// A confirming refit that failed (a diverging filter, an optimiser error) is no evidence against
/// its effect: when the strongest significant suspect's refit failed, the diagnosis names that
/// suspect, says the refit failed and why, and recommends it, instead of calling the misfit
/// outside the catalogue. Returns whether it concluded so.
bool strongest_refit_failed(Result& res) {
  const std::vector<Candidate> ranked = significant_suspects(res);
  if (ranked.empty()) return false;
  const std::string name = ranked.front().name();
  for (const Confirmation& e : res.confirmation.effects)
    if (e.effect == name && !e.error.empty()) {
      res.recommended = {name};
      res.conclusion = "inadequate — suspect " + name + " (" + ranked.front().evidence +
                       ", the strongest) is not confirmed: its held-out refit failed (" + e.error +
                       "); add it and identify again; " + failing_components(res);
      return true;
    }
  return false;
}

}  // namespace

void confirm_suspects(const Model& model, const Dataset& data, const Options& opt, Result& res, Stopwatch& watch) {
  try {
    res.confirmation = confirm_effects(model, data, res.lens, significant_suspects(res), res.suspects, opt.confirm);
  } catch (const std::exception& e) {
    res.confirmation.note = e.what();
  }
  watch.lap(res, "confirmation");
}

void conclude(Result& res, bool confirmed_by_refits) {
  res.recommended.clear();
  res.outside_catalogue = false;
  if (res.adequate()) {
    res.conclusion = "adequate";
    return;
  }
  const ConfirmationReport& c = res.confirmation;
  if (!confirmed_by_refits || !c.ran) {
    for (const Candidate& s : significant_suspects(res)) res.recommended.push_back(s.name());
    res.conclusion = "inadequate — " + (res.recommended.empty() ? std::string("no catalogue effect is significant")
                                                                 : "suspects: " + join(res.recommended, ", ")) +
                     "; " + failing_components(res) +
                     (confirmed_by_refits ? " (not confirmed by refits: " + c.note + ")" : "");
    return;
  }
  std::vector<const Confirmation*> confirmed;  // the order of confirm_jointly: all-data ranking, then held-out gain
  for (const Confirmation& e : c.effects)
    if (e.confirmed) confirmed.push_back(&e);
  std::stable_sort(confirmed.begin(), confirmed.end(), [](const Confirmation* a, const Confirmation* b) {
    const bool sa = std::isfinite(a->all_data_z), sb = std::isfinite(b->all_data_z);
    if (sa != sb) return sa;
    return !sa && (a->loglik_gain > b->loglik_gain || (std::isnan(b->loglik_gain) && !std::isnan(a->loglik_gain)));
  });
  std::vector<std::string> details;
  for (const Confirmation* e : confirmed) {
    res.recommended.push_back(e->effect);
    details.push_back(e->effect + (e->per_record_phase ? " with one phase per record" : "") + " (" +
                      e->reason.substr(e->reason.find(':') + 2) + ")" + unresolved_from(res, e->effect));
  }
  if (!res.recommended.empty()) {
    res.conclusion = "inadequate — add " + join(details, "; ");
    return;
  }
  if (strongest_refit_failed(res)) return;
  const bool huge = smallest_p(res) < 1e-6 * res.threshold;
  res.outside_catalogue = huge;
  const std::string tried = c.effects.empty() ? std::string("no catalogue effect is significant")
                                              : "no significant catalogue effect is confirmed by a refit (" +
                                                    std::to_string(c.effects.size()) + " tried)";
  res.conclusion = std::string("inadequate — ") +
                   (huge ? "the misfit is outside the catalogue: " : "no catalogue effect explains the misfit: ") +
                   failing_components(res) + "; " + tried +
                   (c.residuals.summary.empty() ? std::string() : "; held-out innovations: " + c.residuals.summary);
}

}  // namespace vehs::diagnose::detail

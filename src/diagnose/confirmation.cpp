// Confirmation of the suspects by refits judged on held-out pieces of the user's records
// (confirmation.hpp): the split, the refits the way the model was fitted, and the paired
// held-out criteria (one-step log-likelihood; free-run error for driven models).
#include "vehs/diagnose/confirmation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <optional>

#include "residual_signature.hpp"
#include "twins.hpp"
#include "unit_math.hpp"
#include "vehs/core/error.hpp"
#include "vehs/core/record_phases.hpp"
#include "vehs/diagnose/suspects.hpp"
#include "vehs/fit/fit.hpp"
#include "vehs/identify/identify.hpp"
#include "vehs/likelihood/filter.hpp"
#include "vehs/likelihood/free_run.hpp"
#include "vehs/likelihood/refine.hpp"

namespace vehs::diagnose {

using detail::fmt;

std::string ConfirmationOptions::invalid_reason() const {
  if (!(holdout > 0.05 && holdout < 0.95)) return "confirm.holdout must be in (0.05, 0.95)";
  if (blocks < 3) return "confirm.blocks must be >= 3";
  if (!(z_threshold > 0.0) || !std::isfinite(z_threshold)) return "confirm.z_threshold must be > 0";
  if (!(consistency_margin > 0.0) || !std::isfinite(consistency_margin)) return "confirm.consistency_margin must be > 0";
  if (!(max_samples >= 0.0)) return "confirm.max_samples must be >= 0";
  if (max_effects < 1) return "confirm.max_effects must be >= 1";
  return "";
}

namespace {

constexpr std::size_t kMinPiece = 200;

struct Split {
  Dataset train, held;  ///< held: one record per held-out piece
  std::vector<std::size_t> piece_record;  ///< per piece, its record (in train and data)
};

/// The leading whole records up to max_samples (at least one), their first (1 − holdout) as
/// the training part, the rest cut into pieces (≥ blocks in all, each ≥ kMinPiece samples).
Split split_records(const Dataset& data, const ConfirmationOptions& o) {
  const Dataset used = o.max_samples > 0.0 && double(data.total_samples()) > o.max_samples
                           ? leading_samples(data, [&](std::size_t i, const Record& r, std::size_t taken) {
                               return i > 0 && double(taken + r.size) > o.max_samples ? kEndSelection : r.size;
                             })
                           : data;
  Split s;
  s.train = leading_samples(used, [&](std::size_t, const Record& r, std::size_t) {
    return static_cast<std::size_t>(std::floor((1.0 - o.holdout) * double(r.size)));
  });
  const std::size_t per_record =
      (static_cast<std::size_t>(o.blocks) + used.records.size() - 1) / used.records.size();
  for (std::size_t i = 0; i < used.records.size(); ++i) {
    const Record& r = used.records[i];
    const std::size_t first = s.train.records[i].size, n = r.size - first;
    const std::size_t pieces = std::min(per_record, n / kMinPiece);
    for (std::size_t p = 0; p < pieces; ++p) {
      const std::size_t a = first + p * n / pieces, b = first + (p + 1) * n / pieces;
      Dataset piece;
      Record pr = r;
      pr.offset = 0;
      pr.size = b - a;
      pr.t0 = r.t0 + double(a) * r.dt;
      pr.first_line = r.first_line + a;
      piece.records.push_back(pr);
      piece.x.assign(used.x.begin() + long(r.offset + a), used.x.begin() + long(r.offset + b));
      if (used.has_u()) piece.u.assign(used.u.begin() + long(r.offset + a), used.u.begin() + long(r.offset + b));
      s.held.append(std::move(piece));
      s.piece_record.push_back(i);
    }
  }
  return s;
}

/// A model refitted on the training part, with the measurement noise it is observed with.
struct Refit {
  Model model;
  double measurement_sd = 0.0;
  std::vector<double> record_phases;  ///< harmonic phase per training record (empty: shared)
};

/// How the refits are made and judged: by the likelihood and the filter (a model refined by the
/// likelihood, or data the lens reads as a continuous-time process), else moment fits judged by
/// the held-out suspects' drift contrast (scheme-consistent data).
bool refits_by_likelihood(const Model& model, const Lens& lens) {
  return (model.fit && model.fit->likelihood) || lens.kinematics == Kinematics::Central;
}

InputInterpolation input_of(const Model& model) {
  return model.fit ? model.fit->input : InputInterpolation::ZeroOrderHold;
}

/// The refit's options for vehs::fit: identify's moment fit through the lens with the model's own
/// libraries, then (refits by the likelihood) the likelihood with the support fixed, started at
/// the model's measurement noise and forcing phases when it was so fitted, else at the lens's noise.
/// Effects added to the model's own in a refit: the catalogue's and the user's.
struct Added {
  std::vector<Effect> effects;
  std::vector<UserEffect> user;
};

Added added_of(const Candidate& c) {
  if (c.user) return {{}, {*c.user}};
  return {{Effect{c.id, {}, {}}}, {}};
}

FitOptions refit_fit_options(const Model& model, const Lens& lens, const Dataset& train, const Added& added,
                             bool added_per_record) {
  FitOptions f;
  f.run_checks = false;
  f.moment = refit_options(model, lens);
  f.moment.effects.insert(f.moment.effects.end(), added.effects.begin(), added.effects.end());
  f.moment.user_effects = added.user;
  f.libraries_given = {true, true};
  f.folds_given = true;
  f.likelihood_starts = false;
  LikelihoodSettings& l = f.likelihood;
  l.use = refits_by_likelihood(model, lens) ? LikelihoodUse::Always : LikelihoodUse::Never;
  l.input_auto = false;
  l.record_fit_info = false;
  const LikelihoodFit* lf = model.fit && model.fit->likelihood ? &*model.fit->likelihood : nullptr;
  const double noise_sd = lf ? lf->measurement_sd : lens.sensor_noise_sd;
  if (lf) l.start_record_phases = leading_record_phases(model, train.records.size(), "confirmation");
  if (!l.start_record_phases.empty())  // identify's moment fit has one shared phase: start from the model's forcing
    l.start_effects = {*model.find_effect(EffectId::HarmonicForcing)};
  l.start_measurement_sd = noise_sd;
  l.options = likelihood::RefineOptions{};
  l.options.filter.input = input_of(model);
  l.options.covariance = likelihood::Covariance::Fisher;
  l.options.estimate_measurement_noise = noise_sd > 0.0;
  l.options.measurement_sd_start = noise_sd;
  l.options.per_record_phase = !l.start_record_phases.empty() || added_per_record;
  return f;
}

Refit refit_on(const Model& model, const Lens& lens, const Dataset& train, const Added& added,
               bool added_per_record = false) {
  const FitSummary s = fit(train, refit_fit_options(model, lens, train, added, added_per_record));
  if (!s.refinement.failure.empty()) throw Error(s.refinement.failure);  // a refit that fails is not confirmed
  Refit out{s.model(), lens.sensor_noise_sd, {}};
  if (s.refinement.result) {
    out.measurement_sd = s.refinement.result->model.measurement_sd;
    out.record_phases = s.refinement.result->model.record_phases;
  }
  return out;
}

/// Per held-out piece: the one-step log-likelihood and (driven models) the free-run squared error.
struct PieceScores {
  std::vector<double> loglik, sq_error;
  likelihood::FilterTrace trace;
};

PieceScores score_pieces(const Refit& m, const Split& split, InputInterpolation input, bool with_filter, bool driven,
                         std::size_t skip) {
  const Dataset& held = split.held;
  std::vector<double> phases;  // a phase per record: each piece its record's
  for (std::size_t p = 0; p < split.piece_record.size() && !m.record_phases.empty(); ++p)
    phases.push_back(m.record_phases.at(split.piece_record[p]));
  PieceScores s;
  if (with_filter) {
    likelihood::FilterOptions fo;
    fo.input = input;
    std::size_t longest = 0;
    for (const auto& r : held.records) longest = std::max(longest, r.size);
    fo.block_samples = longest + 1;  // every piece one block, started from its first sample
    s.trace = likelihood::filter_trace({m.model, m.measurement_sd, phases}, held, fo);
  }
  const double twin_bound = driven ? detail::twin_divergence_bound(held) : 0.0;
  for (std::size_t p = 0; p < held.records.size(); ++p) {
    const Record& r = held.records[p];
    if (with_filter) {
      double ll = 0.0;
      for (std::size_t k = r.offset + 1; k < r.offset + r.size; ++k) {
        const double S = s.trace.predicted_var[k], e = held.x[k] - s.trace.predicted_x[k];
        ll += -0.5 * (std::log(2.0 * M_PI * S) + e * e / S);
      }
      s.loglik.push_back(ll);
    }
    if (!driven) continue;
    const std::vector<double> x(held.x.begin() + long(r.offset), held.x.begin() + long(r.offset + r.size));
    const std::vector<double> u(held.u.begin() + long(r.offset), held.u.begin() + long(r.offset + r.size));
    likelihood::FreeRunOptions fr;
    fr.input = input;
    fr.t0 = r.t0;
    fr.divergence_bound = std::max(fr.divergence_bound, twin_bound);  // in the data's units
    Model run = m.model;
    if (!phases.empty())
      for (Effect& e : run.effects)
        if (e.id == EffectId::HarmonicForcing) e.params["phase"] = phases[p];
    const likelihood::Validation v = likelihood::validate_free_run(run, x, u, r.dt, std::min(skip, r.size / 2), fr);
    s.sq_error.push_back(v.rmse * v.rmse);
  }
  return s;
}

double total(const std::vector<double>& v) {
  double s = 0.0;
  for (double a : v) s += a;
  return s;
}

double mean_rmse(const std::vector<double>& sq) { return sq.empty() ? Confirmation::kNaN : std::sqrt(total(sq) / double(sq.size())); }

/// The samples the split uses (training and held out).
std::size_t data_samples(const Split& s) { return s.train.total_samples() + s.held.total_samples(); }

std::vector<double> difference(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> d(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) d[i] = a[i] - b[i];
  return d;
}

/// What the split is judged by (confirmation.hpp, "decision").
struct Judging {
  double z_threshold = 2.0;
  double consistency_margin = 2.5;
  double heldout_share = 0.3;   ///< f
  bool driven = false;
  bool free_run_informative = false;
};

/// The one-step criterion met: by z_threshold, or — with all-data evidence (c.all_data_z) and
/// the filter's criterion — by consistency with that evidence (c.expected_z within the margin,
/// and not worse than the baseline).
bool one_step_met(Confirmation& c, bool filter, const Judging& j) {
  if (c.loglik_gain > 0.0 && c.loglik_z > j.z_threshold) return true;
  if (!filter || !std::isfinite(c.all_data_z) || !std::isfinite(c.loglik_z)) return false;
  c.expected_z = expected_heldout_z(c.all_data_z, j.heldout_share);
  c.by_consistency = c.loglik_z > -j.z_threshold && c.loglik_z >= c.expected_z - j.consistency_margin &&
                     c.refit_innovations.empty();
  return c.by_consistency;
}

/// The free-run criterion met: an improvement by z_threshold where the free run is informative,
/// else no significant worsening.
bool free_run_met(const Confirmation& c, const Judging& j) {
  if (j.free_run_informative) return c.rmse_effect < c.rmse_baseline && c.rmse_z > j.z_threshold;
  return c.rmse_z > -j.z_threshold;
}

/// The one-step criterion from the filter's held-out log-likelihood, else (`heldout`: moment
/// refits of scheme-consistent data) from the held-out suspect's drift contrast (suspects.hpp),
/// which refitted the effect by identify on the same training share.
void judge(Confirmation& c, const PieceScores& base, const PieceScores& with, const Suspect* heldout, const Judging& j) {
  if (heldout) {
    c.loglik_gain = heldout->evidence;
    c.loglik_z = heldout->z;
  } else {
    const std::vector<double> gain = difference(with.loglik, base.loglik);
    c.loglik_gain = total(gain);
    c.loglik_z = block_z(gain);
  }
  const bool one_step_ok = one_step_met(c, heldout == nullptr, j);
  bool run_ok = true;
  if (j.driven) {
    const std::vector<double> drop = difference(base.sq_error, with.sq_error);
    c.rmse_baseline = mean_rmse(base.sq_error);
    c.rmse_effect = mean_rmse(with.sq_error);
    c.rmse_z = block_z(drop);
    run_ok = free_run_met(c, j);
  }
  c.confirmed = one_step_ok && run_ok;
  std::string why = std::string(heldout ? "held-out drift contrast " : "held-out one-step log-likelihood ") + std::string(c.loglik_gain >= 0 ? "+" : "") +
                    fmt(c.loglik_gain) + " nats (z " + fmt(c.loglik_z) + ")";
  if (std::isfinite(c.expected_z) && !c.refit_innovations.empty())
    why += "; the refit's held-out innovations show what no catalogue effect added explains: " + c.refit_innovations;
  else if (std::isfinite(c.expected_z))
    why += std::string(c.by_consistency ? ", in line with" : ", far below") + " the z " + fmt(c.expected_z) +
           " that the all-data score test (z " + fmt(c.all_data_z) + ") predicts for this held-out share";
  if (j.driven)
    why += ", free-run RMSE " + fmt(c.rmse_baseline) + " -> " + fmt(c.rmse_effect) + " (z of the drop " + fmt(c.rmse_z) + ")";
  c.reason = (c.confirmed ? "confirmed: " : "not confirmed: ") + why;
}

void fill_params(Confirmation& c, const Model& m, const Candidate& cand) {
  if (cand.user) {
    const UserEffectFit f = user_effect_fit(m, *cand.user);
    c.params = f.params, c.params_stderr = f.stderr_;
    return;
  }
  const EffectId id = cand.id;
  if (effect_spec(id).term_like) {
    for (const Effect& e : identify::effect_parameters(m, {Effect{id, {}, {}}})) c.params = e.params, c.params_stderr = e.stderr_;
    return;
  }
  if (const Effect* e = m.find_effect(id)) c.params = e->params, c.params_stderr = e->stderr_;
}

/// The parameters that measure an effect's size — those that vanish without it (μ, c, the
/// coupling, the intensity, the amplitude, …; impact_stop has none): not the strictly positive rates and
/// scales (λ, τ, ω, the gap), nor a phase.
bool measures_size(const EffectParamSpec& p) { return !p.strictly_positive && p.name != "phase"; }

/// The parameters of c.effect that measure its size (every parameter of a user's effect).
std::vector<std::string> size_parameters(const Confirmation& c) {
  std::vector<std::string> out;
  if (c.user_effect) {
    for (const auto& [name, value] : c.params) out.push_back(name);
    return out;
  }
  for (const EffectParamSpec& p : effect_spec(enum_from_string(kEffectNames, c.effect, "effect")).params)
    if (measures_size(p)) out.emplace_back(p.name);
  return out;
}

/// "coupling 0.114 ± 0.074 (z 1.5)" for those parameters.
std::string size_text(const Confirmation& c) {
  std::string t;
  for (const std::string& p : size_parameters(c)) {
    const auto v = c.params.find(p);
    const auto se = c.params_stderr.find(p);
    if (v == c.params.end() || se == c.params_stderr.end() || !(se->second > 0.0)) continue;
    t += (t.empty() ? "" : ", ") + p + " " + fmt(v->second) + " ± " + fmt(se->second) + " (z " +
         fmt(std::abs(v->second) / se->second) + ")";
  }
  return t.empty() ? "no size parameter with a standard error" : t;
}

/// Effects confirmed one at a time can be one explanation twice (a y³ damping absorbs part of a
/// hidden Coulomb friction: both improve on the baseline). The first in the all-data ranking
/// stays confirmed (held-out evidence only: the largest gain); each further one must improve on
/// the refit with those kept before it by z_threshold, else it is not confirmed ("adds nothing
/// beyond …"). Needs the filter's criterion (refits by the likelihood).
void confirm_jointly(ConfirmationReport& rep, const std::vector<Candidate>& tried,
                     const std::vector<PieceScores>& alone_scores, const Model& model, const Lens& lens,
                     const Split& split, const Judging& judging, const ConfirmationOptions& o) {
  const InputInterpolation input = input_of(model);
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < rep.effects.size(); ++i)
    if (rep.effects[i].confirmed) order.push_back(i);
  // the all-data evidence first, in its ranking (score tests by p, look-alikes as their refits'
  // likelihood ratio ordered them: better evidence than a 30 % share), then held-out evidence by gain
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const bool sa = std::isfinite(rep.effects[a].all_data_z), sb = std::isfinite(rep.effects[b].all_data_z);
    if (sa != sb) return sa;
    return !sa && rep.effects[a].loglik_gain > rep.effects[b].loglik_gain;
  });
  if (order.size() < 2) return;
  Added kept = added_of(tried[order[0]]);
  std::string kept_names = rep.effects[order[0]].effect;
  PieceScores kept_scores = alone_scores[order[0]];
  bool per_record = rep.effects[order[0]].per_record_phase;  // a kept forcing with one phase per record
  for (std::size_t k = 1; k < order.size(); ++k) {
    Confirmation& c = rep.effects[order[k]];
    const std::string alone = c.reason.substr(c.reason.find(':') + 2);
    const Candidate& cand = tried[order[k]];
    if (!cand.user && std::any_of(kept.effects.begin(), kept.effects.end(), [&](const Effect& e) { return e.id == cand.id; })) {
      c.confirmed = false;  // the shared and the per-record forcing: one form is kept
      c.reason = "not confirmed: the other form of " + c.effect + " is kept (alone: " + alone + ")";
      continue;
    }
    Added with_effects = kept;
    const Added mine = added_of(cand);
    with_effects.effects.insert(with_effects.effects.end(), mine.effects.begin(), mine.effects.end());
    with_effects.user.insert(with_effects.user.end(), mine.user.begin(), mine.user.end());
    Confirmation joint;
    joint.effect = c.effect;
    try {
      const Refit r = refit_on(model, lens, split.train, with_effects, per_record || c.per_record_phase);
      joint.user_effect = c.user_effect;
      fill_params(joint, r.model, cand);
      PieceScores with = score_pieces(r, split, input, true, rep.driven, o.free_run_skip);
      with.trace = {};
      judge(joint, kept_scores, with, nullptr, judging);  // no all-data evidence beyond the kept: z_threshold
      if (joint.confirmed && effect_size_z(joint) <= o.z_threshold) {
        c.reason = "not confirmed: beyond " + kept_names + " its size is not significant in the joint refit (" + size_text(joint) +
                   "; " + joint.reason.substr(joint.reason.find(':') + 2) + "; alone: " + alone + ")";
        c.confirmed = false;
        continue;
      }
      if (joint.confirmed) {
        c.reason = "confirmed: " + alone + "; beyond " + kept_names + ": " + joint.reason.substr(joint.reason.find(':') + 2);
        kept = std::move(with_effects);
        kept_names += " and " + c.effect;
        kept_scores = std::move(with);
        per_record = per_record || c.per_record_phase;
        continue;
      }
      c.reason = "not confirmed: adds nothing beyond " + kept_names + " (" + joint.reason.substr(joint.reason.find(':') + 2) +
                 "; alone: " + alone + ")";
    } catch (const std::exception& e) {
      c.reason = "not confirmed: the refit with " + kept_names + " failed: " + e.what() + " (alone: " + alone + ")";
    }
    c.confirmed = false;
  }
}

}  // namespace

double expected_heldout_z(double all_data_z, double heldout_share) { return 0.5 * std::sqrt(heldout_share) * all_data_z; }

ConfirmationReport confirm_effects(const Model& model, const Dataset& data, const Lens& lens,
                                   const std::vector<Candidate>& candidates, const SuspectReport& heldout,
                                   const ConfirmationOptions& o) {
  if (auto why = o.invalid_reason(); !why.empty()) throw Error(why);
  const auto t0 = std::chrono::steady_clock::now();
  ConfirmationReport rep;
  const Split split = split_records(data, o);
  rep.train_samples = split.train.total_samples();
  rep.heldout_samples = split.held.total_samples();
  rep.pieces = static_cast<int>(split.held.records.size());
  rep.driven = model.uses_drive() && split.held.has_u();
  rep.by_likelihood = refits_by_likelihood(model, lens);
  const bool by_filter = rep.by_likelihood;
  const InputInterpolation input = input_of(model);
  rep.criterion = std::string("refits on the first ") + fmt(100.0 * (1.0 - o.holdout), 3) +
                  " % of every record (identify" + (by_filter ? " + maximum likelihood" : "") +
                  "), judged on the rest: " +
                  (by_filter ? "the filter's one-step log-likelihood on " + std::to_string(rep.pieces) +
                                   " pieces must improve by > " + fmt(o.z_threshold) +
                                   " standard errors or be what the all-data score test predicts for this share (within " +
                                   fmt(o.consistency_margin) + " standard errors, and not worse)"
                             : "the held-out suspects' one-step drift contrast must improve by > " + fmt(o.z_threshold) +
                                   " standard errors");
  auto heldout_of = [&](const std::string& name) -> const Suspect* {
    for (const Suspect& sp : heldout.ranked)
      if (sp.effect == name && std::isfinite(sp.z)) return &sp;
    return nullptr;
  };
  if (rep.pieces < 3) {
    rep.note = "too few held-out samples for " + std::to_string(o.blocks) + " pieces of " + std::to_string(kMinPiece);
    return rep;
  }
  PieceScores base;
  try {
    if (by_filter || rep.driven)
      base = score_pieces(refit_on(model, lens, split.train, {}), split, input, by_filter, rep.driven, o.free_run_skip);
  } catch (const std::exception& e) {
    rep.note = std::string("the baseline refit on the training part failed: ") + e.what();
    return rep;
  }
  rep.ran = true;
  rep.baseline_loglik = by_filter ? total(base.loglik) : Confirmation::kNaN;
  rep.baseline_rmse = mean_rmse(base.sq_error);
  Judging judging{o.z_threshold, o.consistency_margin, double(rep.heldout_samples) / double(data_samples(split)),
                  rep.driven, false};
  if (rep.driven) {
    rep.heldout_sd = std::sqrt(pooled_record_variance(split.held));
    judging.free_run_informative = rep.free_run_informative = rep.baseline_rmse < 0.5 * rep.heldout_sd;
    rep.criterion += std::string("; the free-run RMSE on ") + std::to_string(rep.pieces) + " pieces must " +
                     (rep.free_run_informative ? "improve by > " + fmt(o.z_threshold) + " standard errors"
                                               : "not get worse by > " + fmt(o.z_threshold) +
                                                     " standard errors (the baseline's free run, RMSE " +
                                                     fmt(rep.baseline_rmse) + " against a held-out sd of x of " +
                                                     fmt(rep.heldout_sd) + ", does not predict the response)");
  }
  // the filter's innovations describe the misfit of a continuous-time model (a moment fit to
  // scheme-consistent data is not the continuous-time model the filter assumes)
  if (by_filter) rep.residuals = residual_signature(split.held, base.trace, lens.dt);
  std::vector<PieceScores> alone_scores;  // per candidate, when refitted (the filter's trace dropped)
  for (const Candidate& cand : candidates) {
    if (static_cast<int>(rep.effects.size()) >= o.max_effects) break;
    Confirmation c;
    c.effect = cand.name();
    c.user_effect = cand.user.has_value();
    c.per_record_phase = cand.per_record_phase;
    c.evidence = cand.evidence;
    c.all_data_z = cand.all_data_z;
    try {
      const Suspect* h = by_filter ? nullptr : heldout_of(cand.name());
      if (!by_filter && !h) throw Error("no held-out evidence (the held-out suspects did not test it)");
      PieceScores with;
      if (by_filter || rep.driven) {
        const Refit r = refit_on(model, lens, split.train, added_of(cand), cand.per_record_phase);
        fill_params(c, r.model, cand);
        with = score_pieces(r, split, input, by_filter, rep.driven, o.free_run_skip);
        if (by_filter)
          if (const ResidualSignature sig = residual_signature(split.held, with.trace, lens.dt); sig.features > 0)
            c.refit_innovations = sig.summary;
      } else {
        c.params = h->params;
        c.params_stderr = h->params_stderr;
      }
      // a term-like effect is stored as terms, so no file refuses e.g. a negative friction:
      // a recommendation must still be the catalogue's effect (Silverbox, second round:
      // coulomb_friction refitted with mu = −8.4)
      if (const std::string why = cand.user ? "" : effect_domain_violation(Effect{cand.id, c.params, {}}); !why.empty())
        throw Error("the refit is not usable: " + why);
      judge(c, base, with, h, judging);
      with.trace = {};
      alone_scores.push_back(std::move(with));
    } catch (const std::exception& e) {
      c.error = e.what();
      c.reason = std::string("not confirmed: the refit failed: ") + e.what();
      alone_scores.emplace_back();
    }
    rep.effects.push_back(std::move(c));
  }
  if (by_filter) confirm_jointly(rep, candidates, alone_scores, model, lens, split, judging, o);
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

double effect_size_z(const Confirmation& c) {
  double z = Confirmation::kNaN;
  for (const std::string& p : size_parameters(c)) {
    const auto v = c.params.find(p);
    const auto se = c.params_stderr.find(p);
    if (v != c.params.end() && se != c.params_stderr.end() && se->second > 0.0)
      z = std::isnan(z) ? std::abs(v->second) / se->second : std::max(z, std::abs(v->second) / se->second);
  }
  return z;
}

}  // namespace vehs::diagnose

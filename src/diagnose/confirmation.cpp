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
#include "unit_math.hpp"
#include "vehs/core/error.hpp"
#include "vehs/core/record_phases.hpp"
#include "vehs/diagnose/suspects.hpp"
#include "vehs/identify/identify.hpp"
#include "vehs/likelihood/filter.hpp"
#include "vehs/likelihood/free_run.hpp"
#include "vehs/likelihood/record_phase_start.hpp"
#include "vehs/likelihood/refine.hpp"

namespace vehs::diagnose {

using detail::fmt;

std::string ConfirmationOptions::invalid_reason() const {
  if (!(holdout > 0.05 && holdout < 0.95)) return "confirm.holdout must be in (0.05, 0.95)";
  if (blocks < 3) return "confirm.blocks must be >= 3";
  if (!(z_threshold > 0.0) || !std::isfinite(z_threshold)) return "confirm.z_threshold must be > 0";
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

Refit refit_on(const Model& model, const Lens& lens, const Dataset& train, const std::vector<Effect>& added,
               bool added_per_record = false) {
  identify::Options io = refit_options(model, lens);
  io.effects.insert(io.effects.end(), added.begin(), added.end());
  Refit out;
  out.model = identify::identify(train, io).model;
  out.measurement_sd = lens.sensor_noise_sd;
  if (!model.fit || !model.fit->likelihood) return out;
  // the model was refined by maximum likelihood: so is the refit (support fixed)
  const LikelihoodFit& lf = *model.fit->likelihood;
  const std::vector<double> phases = leading_record_phases(model, train.records.size(), "confirmation");
  if (!phases.empty())  // identify's moment fit has one shared phase: start from the model's forcing
    for (Effect& e : out.model.effects)
      if (e.id == EffectId::HarmonicForcing) e.params = model.find_effect(EffectId::HarmonicForcing)->params;
  likelihood::ObservedModel start{out.model, lf.measurement_sd, phases};
  likelihood::RefineOptions ro;
  ro.filter.input = model.fit->input;
  if (phases.empty() && added_per_record)  // each record's own moment fit: its phase (as identify-vehs)
    likelihood::start_record_phases(start, train, [&](const Dataset& one) { return identify::identify(one, io).model; },
                                    ro.filter);
  ro.covariance = likelihood::Covariance::Fisher;
  ro.estimate_measurement_noise = lf.measurement_sd > 0.0;
  ro.measurement_sd_start = lf.measurement_sd;
  ro.per_record_phase = !start.record_phases.empty();
  const likelihood::Result r = likelihood::refine(start, train, ro);
  const std::optional<FitInfo> fit = out.model.fit;
  out.model = r.model.model;
  out.model.fit = fit;
  if (out.model.fit) out.model.fit->input = model.fit->input;
  out.measurement_sd = r.model.measurement_sd;
  out.record_phases = r.model.record_phases;
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

std::vector<double> difference(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> d(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) d[i] = a[i] - b[i];
  return d;
}

/// The one-step criterion from the filter's held-out log-likelihood, else (`heldout`: a model
/// not fitted by likelihood) from the held-out suspect's drift contrast (suspects.hpp), which
/// refitted the effect by identify on the same training share.
void judge(Confirmation& c, const PieceScores& base, const PieceScores& with, const Suspect* heldout, bool driven,
           double z_threshold) {
  if (heldout) {
    c.loglik_gain = heldout->evidence;
    c.loglik_z = heldout->z;
  } else {
    const std::vector<double> gain = difference(with.loglik, base.loglik);
    c.loglik_gain = total(gain);
    c.loglik_z = block_z(gain);
  }
  const bool likelihood_ok = c.loglik_gain > 0.0 && c.loglik_z > z_threshold;
  bool run_ok = true;
  if (driven) {
    const std::vector<double> drop = difference(base.sq_error, with.sq_error);
    c.rmse_baseline = mean_rmse(base.sq_error);
    c.rmse_effect = mean_rmse(with.sq_error);
    c.rmse_z = block_z(drop);
    run_ok = c.rmse_effect < c.rmse_baseline && c.rmse_z > z_threshold;
  }
  c.confirmed = likelihood_ok && run_ok;
  std::string why = std::string(heldout ? "held-out drift contrast " : "held-out one-step log-likelihood ") + std::string(c.loglik_gain >= 0 ? "+" : "") +
                    fmt(c.loglik_gain) + " nats (z " + fmt(c.loglik_z) + ")";
  if (driven)
    why += ", free-run RMSE " + fmt(c.rmse_baseline) + " -> " + fmt(c.rmse_effect) + " (z of the drop " + fmt(c.rmse_z) + ")";
  c.reason = (c.confirmed ? "confirmed: " : "not confirmed: ") + why;
}

void fill_params(Confirmation& c, const Model& m, EffectId id) {
  if (effect_spec(id).term_like) {
    for (const Effect& e : identify::effect_parameters(m, {Effect{id, {}, {}}})) c.params = e.params, c.params_stderr = e.stderr_;
    return;
  }
  if (const Effect* e = m.find_effect(id)) c.params = e->params, c.params_stderr = e->stderr_;
}

/// Effects confirmed one at a time can be one explanation twice (a y³ damping absorbs part of a
/// hidden Coulomb friction: both improve on the baseline). The one with the largest held-out
/// gain stays confirmed; each further one, in the order of its gain, must improve on the refit
/// with those kept before it by the same criterion, else it is not confirmed ("adds nothing
/// beyond …"). Needs the filter's criterion (a model fitted by the likelihood).
void confirm_jointly(ConfirmationReport& rep, const std::vector<PieceScores>& alone_scores, const Model& model,
                     const Lens& lens, const Split& split, InputInterpolation input, const ConfirmationOptions& o) {
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < rep.effects.size(); ++i)
    if (rep.effects[i].confirmed) order.push_back(i);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return rep.effects[a].loglik_gain > rep.effects[b].loglik_gain; });
  if (order.size() < 2) return;
  std::vector<Effect> kept{Effect{enum_from_string(kEffectNames, rep.effects[order[0]].effect, "effect"), {}, {}}};
  std::string kept_names = rep.effects[order[0]].effect;
  PieceScores kept_scores = alone_scores[order[0]];
  bool per_record = rep.effects[order[0]].per_record_phase;  // a kept forcing with one phase per record
  for (std::size_t k = 1; k < order.size(); ++k) {
    Confirmation& c = rep.effects[order[k]];
    const std::string alone = c.reason.substr(c.reason.find(':') + 2);
    const EffectId id = enum_from_string(kEffectNames, c.effect, "effect");
    if (std::any_of(kept.begin(), kept.end(), [&](const Effect& e) { return e.id == id; })) {
      c.confirmed = false;  // the shared and the per-record forcing: one form is kept
      c.reason = "not confirmed: the other form of " + c.effect + " is kept (alone: " + alone + ")";
      continue;
    }
    std::vector<Effect> with_effects = kept;
    with_effects.push_back(Effect{id, {}, {}});
    Confirmation joint;
    try {
      PieceScores with = score_pieces(refit_on(model, lens, split.train, with_effects, per_record || c.per_record_phase),
                                      split, input, true, rep.driven, o.free_run_skip);
      with.trace = {};
      judge(joint, kept_scores, with, nullptr, rep.driven, o.z_threshold);
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
  const bool likelihood_fit = model.fit && model.fit->likelihood;
  const InputInterpolation input = model.fit ? model.fit->input : InputInterpolation::ZeroOrderHold;
  rep.criterion = std::string("refits on the first ") + fmt(100.0 * (1.0 - o.holdout), 3) +
                  " % of every record (identify" + (likelihood_fit ? " + maximum likelihood" : "") +
                  ", as the model was fitted), judged on the rest: " +
                  (likelihood_fit ? "the filter's one-step log-likelihood on " + std::to_string(rep.pieces) + " pieces"
                                  : std::string("the held-out suspects' one-step drift contrast")) +
                  (rep.driven ? " and the free-run RMSE on " + std::to_string(rep.pieces) + " pieces" : std::string()) +
                  " must improve by > " + fmt(o.z_threshold) + " standard errors";
  auto heldout_of = [&](EffectId id) -> const Suspect* {
    for (const Suspect& sp : heldout.ranked)
      if (sp.effect == enum_to_string(kEffectNames, id) && std::isfinite(sp.z)) return &sp;
    return nullptr;
  };
  if (rep.pieces < 3) {
    rep.note = "too few held-out samples for " + std::to_string(o.blocks) + " pieces of " + std::to_string(kMinPiece);
    return rep;
  }
  PieceScores base;
  try {
    if (likelihood_fit || rep.driven)
      base = score_pieces(refit_on(model, lens, split.train, {}), split, input, likelihood_fit, rep.driven,
                          o.free_run_skip);
  } catch (const std::exception& e) {
    rep.note = std::string("the baseline refit on the training part failed: ") + e.what();
    return rep;
  }
  rep.ran = true;
  rep.baseline_loglik = likelihood_fit ? total(base.loglik) : Confirmation::kNaN;
  rep.baseline_rmse = mean_rmse(base.sq_error);
  // the filter's innovations describe the misfit of a model fitted by the likelihood (a moment
  // fit to scheme-consistent data is not the continuous-time model the filter assumes)
  if (likelihood_fit) rep.residuals = residual_signature(split.held, base.trace, lens.dt);
  std::vector<PieceScores> alone_scores;  // per candidate, when refitted (the filter's trace dropped)
  for (const Candidate& cand : candidates) {
    if (static_cast<int>(rep.effects.size()) >= o.max_effects) break;
    Confirmation c;
    c.effect = enum_to_string(kEffectNames, cand.id);
    c.per_record_phase = cand.per_record_phase;
    c.evidence = cand.evidence;
    try {
      const Suspect* h = likelihood_fit ? nullptr : heldout_of(cand.id);
      if (!likelihood_fit && !h) throw Error("no held-out evidence (the held-out suspects did not test it)");
      PieceScores with;
      if (likelihood_fit || rep.driven) {
        const Refit r = refit_on(model, lens, split.train, {Effect{cand.id, {}, {}}}, cand.per_record_phase);
        fill_params(c, r.model, cand.id);
        with = score_pieces(r, split, input, likelihood_fit, rep.driven, o.free_run_skip);
      } else {
        c.params = h->params;
        c.params_stderr = h->params_stderr;
      }
      // a term-like effect is stored as terms, so no file refuses e.g. a negative friction:
      // a recommendation must still be the catalogue's effect (Silverbox, second round:
      // coulomb_friction refitted with mu = −8.4)
      if (const std::string why = effect_domain_violation(Effect{cand.id, c.params, {}}); !why.empty())
        throw Error("the refit puts " + why);
      judge(c, base, with, h, rep.driven, o.z_threshold);
      with.trace = {};
      alone_scores.push_back(std::move(with));
    } catch (const std::exception& e) {
      c.error = e.what();
      c.reason = std::string("not confirmed: the refit failed: ") + e.what();
      alone_scores.emplace_back();
    }
    rep.effects.push_back(std::move(c));
  }
  if (likelihood_fit) confirm_jointly(rep, alone_scores, model, lens, split, input, o);
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

}  // namespace vehs::diagnose

#include "vehs/diagnose/suspects.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <mutex>

#include "vehs/core/error.hpp"
#include "vehs/core/detail/progress_counter.hpp"
#include "vehs/identify/dynamic.hpp"
#include "vehs/identify/identify.hpp"

namespace vehs::diagnose {

const std::vector<SuspectEntry>& suspect_table() {
  static const std::vector<SuspectEntry> table = {
      {EffectId::AsymmetricStiffness, SuspectMethod::DriftTerms, ""},
      {EffectId::CoulombFriction, SuspectMethod::DriftTerms, ""},
      {EffectId::QuadraticDamping, SuspectMethod::DriftTerms, ""},
      {EffectId::NonlinearDamping, SuspectMethod::DriftTerms, ""},
      {EffectId::ImpactStop, SuspectMethod::DynamicForce, ""},
      {EffectId::HarmonicForcing, SuspectMethod::DynamicForce, ""},
      {EffectId::ElectromechanicalCoupling, SuspectMethod::DynamicForce, ""},
      {EffectId::ColoredNoise, SuspectMethod::ColoredExcitation, ""},
      {EffectId::VelocityDependentNoise, SuspectMethod::DiffusionTerms, ""},
  };
  return table;
}

std::string SuspectOptions::invalid_reason() const {
  if (!(holdout > 0.05 && holdout < 0.95)) return "suspects.holdout must be in (0.05, 0.95)";
  if (!(z_threshold > 0.0) || !std::isfinite(z_threshold)) return "suspects.z_threshold must be > 0";
  if (min_blocks < 2) return "suspects.min_blocks must be >= 2";
  return "";
}

namespace {

Dataset training_part(const Dataset& d, double holdout) {
  return leading_samples(d, [holdout](std::size_t, const Record& r, std::size_t) {
    return static_cast<std::size_t>(std::floor((1.0 - holdout) * static_cast<double>(r.size)));
  });
}

struct Fitted {
  std::string name;
  SuspectMethod method = SuspectMethod::DriftTerms;
  Effect effect;
  const UserEffect* user = nullptr;  ///< a user's effect (then `effect` is unused)
  Model model;
  CompiledTerms drift, diffusion;
  std::vector<std::string> added;
};

/// Held-out sums of one block: drift contrast per candidate (weighted), diffusion
/// log-likelihood per candidate, rows.
struct BlockSums {
  std::vector<double> contrast, loglik;
  double rows = 0.0;
  bool invalid_variance = false;
};

}  // namespace

double block_z(const std::vector<double>& gain) {
  const double B = static_cast<double>(gain.size());
  if (B < 2) return 0.0;
  double mean = 0.0, ss = 0.0;
  for (double g : gain) mean += g;
  mean /= B;
  for (double g : gain) ss += (g - mean) * (g - mean);
  const double se = std::sqrt(ss / (B - 1) / B);
  return se > 0 ? mean / se : 0.0;
}

std::string refit_text(const Suspect& suspect) {
  if (!suspect.refit_error.empty()) return "refit failed: " + suspect.refit_error;
  return suspect.refit_verdict ? enum_to_string(kVerdictNames, *suspect.refit_verdict) : "";
}

SuspectMethod suspect_method(EffectId id) {
  for (const auto& e : suspect_table())
    if (e.id == id) return e.method;
  return SuspectMethod::NotYet;
}

SuspectMethod suspect_method(const std::string& effect) {
  for (const auto& e : suspect_table())
    if (enum_to_string(kEffectNames, e.id) == effect) return e.method;
  return SuspectMethod::DriftTerms;
}

identify::Options refit_options(const Model& model, const Lens& lens) {
  identify::Options io;
  io.drift_library = terms_of(model.drift);
  io.diffusion_library = terms_of(model.diffusion);
  io.sparsity = identify::Sparsity::None;
  for (const auto& e : model.effects) {
    Effect refit;  // the model's dynamic effects are refitted (all params free)
    refit.id = e.id;
    io.effects.push_back(refit);
  }
  io.folds = 1;  // no cross-validation: the support is fixed
  if (lens.kinematics == Kinematics::Forward) {
    io.estimator = Estimator::Forward;
  } else {
    io.estimator = lens.sensor_noise_sd > 0.0 ? Estimator::Noisy : Estimator::Uli;
    io.stride = lens.stride;
  }
  return io;
}

SuspectReport rank_suspects(const Model& model, const Dataset& data, const Lens& lens,
                            const SuspectOptions& options) {
  SuspectReport rep;
  if (auto why = options.invalid_reason(); !why.empty()) throw Error(why);
  if (auto why = lens.invalid_reason(); !why.empty()) throw Error("lens: " + why);

  // ---- which effects are candidates
  std::vector<const SuspectEntry*> candidates;
  for (const auto& e : suspect_table()) {
    const std::string name = enum_to_string(kEffectNames, e.id);
    if (!options.only.empty() && std::find(options.only.begin(), options.only.end(), e.id) == options.only.end())
      continue;
    if (e.method == SuspectMethod::NotYet) {
      rep.untested.emplace_back(name, std::string(e.note));
      continue;
    }
    candidates.push_back(&e);
  }
  const bool model_colored = model.find_effect(EffectId::ColoredNoise) != nullptr;
  for (const auto& e : model.effects)
    if (!identify::dynamic_fit_supported(e.id) || (model_colored && e.id != EffectId::ColoredNoise)) {
      if (identify::dynamic_fit_supported(e.id)) {
        rep.note = "the model has colored_noise together with the dynamic effect " + e.name() +
                   ", which identify cannot refit together yet, so the baseline of the suspects cannot be fitted";
        for (const auto* c : candidates) rep.untested.emplace_back(enum_to_string(kEffectNames, c->id), rep.note);
        return rep;
      }
      rep.note = "the model has the dynamic effect " + e.name() +
                 ", which identify cannot refit yet, so the baseline of the suspects cannot be fitted";
      for (const auto* c : candidates) rep.untested.emplace_back(enum_to_string(kEffectNames, c->id), rep.note);
      return rep;
    }
  if (model.drift.empty()) {
    rep.note = "the model has no drift terms to refit";
    return rep;
  }

  // ---- fits on the training part
  const Dataset train = training_part(data, options.holdout);
  const identify::Options io = refit_options(model, lens);
  std::vector<Fitted> fits;
  vehs::detail::ProgressCounter prog(options.progress, "suspects",
                                     static_cast<long long>(candidates.size() + options.user_effects.size()) + 2);
  double sensor_sd = lens.sensor_noise_sd;
  try {
    const identify::Result base = identify::identify(train, io);
    Fitted f;
    f.name = "baseline";
    f.model = base.model;
    fits.push_back(std::move(f));
    if (io.estimator == Estimator::Noisy) sensor_sd = base.model.fit->sampling.sensor_noise_sd;
  } catch (const std::exception& e) {
    rep.note = std::string("the baseline refit on the training part failed: ") + e.what();
    return rep;
  }
  prog.advance();
  for (const auto* c : candidates) {
    const std::string name = enum_to_string(kEffectNames, c->id);
    std::vector<std::string> added;
    if (c->method == SuspectMethod::DynamicForce || c->method == SuspectMethod::ColoredExcitation) {
      if (model.find_effect(c->id)) {
        rep.untested.emplace_back(name, "already in the model");
        prog.advance();
        continue;
      }
      added.push_back(name + (c->method == SuspectMethod::DynamicForce ? " (dynamic force)" : " (OU excitation)"));
    } else {
      const EffectTerms et = unit_effect_terms(c->id);
      for (const auto& tc : et.drift)
        if (coefficient(model.drift, tc.term) == 0.0) added.push_back(tc.term.name());
      for (const auto& tc : et.diffusion)
        if (coefficient(model.diffusion, tc.term) == 0.0) added.push_back(tc.term.name() + " (diffusion)");
      if (added.empty()) {
        rep.untested.emplace_back(name, "its terms are already in the model");
        prog.advance();
        continue;
      }
    }
    identify::Options o = io;
    Effect req;
    req.id = c->id;
    o.effects.push_back(req);
    try {
      const identify::Result r = identify::identify(train, o);
      Fitted f;
      f.name = name;
      f.method = c->method;
      f.effect = req;
      f.model = r.model;
      f.added = added;
      fits.push_back(std::move(f));
    } catch (const std::exception& e) {
      rep.untested.emplace_back(name, std::string("the fit failed: ") + e.what());
    }
    prog.advance();
  }
  for (const UserEffect& u : options.user_effects) {
    std::vector<std::string> added;
    bool drift = false;
    for (const UserEffectParam& p : u.params) {
      if (coefficient(p.diffusion ? model.diffusion : model.drift, p.term) != 0.0) continue;
      added.push_back(p.term.name() + (p.diffusion ? " (diffusion)" : ""));
      drift = drift || !p.diffusion;
    }
    if (added.empty()) {
      rep.untested.emplace_back(u.name, "its terms are already in the model");
    } else {
      identify::Options o = io;
      o.user_effects.push_back(u);
      try {
        Fitted f;
        f.name = u.name;
        f.method = drift ? SuspectMethod::DriftTerms : SuspectMethod::DiffusionTerms;
        f.user = &u;
        f.model = identify::identify(train, o).model;
        f.added = added;
        fits.push_back(std::move(f));
      } catch (const std::exception& e) {
        rep.untested.emplace_back(u.name, std::string("the fit failed: ") + e.what());
      }
    }
    prog.advance();
  }
  for (auto& f : fits) {
    f.drift = CompiledTerms(f.model.drift);
    f.diffusion = CompiledTerms(f.model.diffusion);
  }

  // ---- held-out blocks
  struct Block {
    std::size_t record, begin, end;  // sample range of row centres
  };
  std::vector<Block> blocks;
  const std::size_t nrec = data.records.size();
  const std::size_t per = nrec >= static_cast<std::size_t>(options.min_blocks)
                              ? 1
                              : (static_cast<std::size_t>(options.min_blocks) + nrec - 1) / nrec;
  for (std::size_t r = 0; r < nrec; ++r) {
    const std::size_t n = data.records[r].size;
    const std::size_t split = train.records[r].size;
    const std::size_t b0 = std::max(split, lens.lead());
    const std::size_t e0 = n > lens.trail() ? n - lens.trail() : 0;
    if (e0 <= b0) continue;
    for (std::size_t p = 0; p < per; ++p)
      blocks.push_back({r, b0 + (e0 - b0) * p / per, b0 + (e0 - b0) * (p + 1) / per});
  }
  const ModelLens base_lens(fits[0].model, Lens{lens.kinematics, lens.stride, lens.dt, sensor_sd});
  // sign-kernel half-width of the Itô correction: 5 % of the rms velocity (as identify)
  double v2 = 0.0, nv = 0.0;
  for (const auto& b : blocks) {
    const double* x = data.x_of(data.records[b.record]);
    for (std::size_t i = b.begin; i < b.end; i += 16) {
      double xi, v, a;
      lens.at(x, i, xi, v, a);
      v2 += v * v;
      nv += 1.0;
    }
  }
  const double sign_w = std::max(0.05 * std::sqrt(v2 / std::max(nv, 1.0)), 1e-300);
  const bool central = lens.kinematics == Kinematics::Central;
  const double h = lens.h(), c = lens.c();
  const double s2 = sensor_sd * sensor_sd;
  const double noise_var = 6.0 * s2 / (h * h * h * h);
  const double var_v_noise = central ? s2 / (2.0 * h * h) : 0.0;
  const double ax_cov = central ? 2.0 * s2 / (h * h) : 0.0;
  // floor of the reference variance: 5 % of its mean over the held-out rows
  double mean_var = 0.0, nmv = 0.0;
  for (const auto& b : blocks) {
    const double* x = data.x_of(data.records[b.record]);
    for (std::size_t i = b.begin; i < b.end; i += 64) {
      mean_var += c * base_lens.a22(x[i], 0.0) / h + noise_var;
      nmv += 1.0;
    }
  }
  const double var_floor = std::max(0.05 * std::abs(mean_var / std::max(nmv, 1.0)), 1e-300);

  const std::size_t K = fits.size();
  std::vector<BlockSums> sums(blocks.size());
#pragma omp parallel for schedule(dynamic, 1)
  for (long bi = 0; bi < static_cast<long>(blocks.size()); ++bi) {
    const Block& b = blocks[static_cast<std::size_t>(bi)];
    BlockSums& s = sums[static_cast<std::size_t>(bi)];
    s.contrast.assign(K, 0.0);
    s.loglik.assign(K, 0.0);
    const Record& rec = data.records[b.record];
    const double* x = data.x_of(rec);
    const double* u = data.u_of(rec);
    // forces of the dynamic effects of every fit along the record (absolute time, hidden
    // states filtered from the record's start)
    std::vector<std::vector<double>> dyn(K);
    for (std::size_t k = 0; k < K; ++k) {
      if (fits[k].model.effects.empty()) continue;
      identify::dynamic_force(fits[k].model.effects, data, rec, dyn[k], central ? lens.stride : 0);
      // colored_noise: the excitation predicted from the record's past (rows up to i − 2k)
      if (const Effect* cn = fits[k].model.find_effect(EffectId::ColoredNoise); cn && central) {
        std::vector<double> pred;
        identify::colored_prediction(*cn, fits[k].model.drift, fits[k].model.diffusion, x, u, rec.size, rec.dt,
                                     lens.stride, pred);
        for (std::size_t i = 0; i < rec.size; ++i) dyn[k][i] += pred[i];
      }
    }
    for (std::size_t i = b.begin; i < b.end; ++i) {
      double xi, v, a;
      lens.at(x, i, xi, v, a);
      const double ui = u ? u[i] : 0.0;
      const double a22b = fits[0].diffusion.value(xi, v, 0.0);
      const double ref_var = std::max(c * fits[0].diffusion.value(xi, 0.0, 0.0) / h + noise_var, var_floor);
      const double w = 0.5 / ref_var;
      const double Fb = fits[0].drift.value(xi, v, ui) + (dyn[0].empty() ? 0.0 : dyn[0][i]);
      for (std::size_t k = 0; k < K; ++k) {
        const Fitted& f = fits[k];
        const double F = k == 0 ? Fb : f.drift.value(xi, v, ui) + (dyn[k].empty() ? 0.0 : dyn[k][i]);
        double C = (a - F) * (a - F);
        if (central) {
          const double dF = f.drift.d_dy(xi, v, sign_w);
          C += a22b * dF;
          if (var_v_noise != 0.0)
            C -= var_v_noise * (dF * dF + F * f.drift.d2_dy2(xi, v)) + 2.0 * ax_cov * f.drift.d_dx(xi, v);
        }
        s.contrast[k] += w * C;
        const double var = c * f.diffusion.value(xi, v, 0.0) / h + noise_var;
        if (var > 0.0)
          s.loglik[k] += -0.5 * (std::log(var) + (a - Fb) * (a - Fb) / var);
        else
          s.invalid_variance = true;
      }
      s.rows += 1.0;
    }
  }
  prog.advance();
  prog.finish();

  rep.blocks = static_cast<int>(blocks.size());
  for (const auto& s : sums) rep.baseline_heldout_rows += s.rows;
  for (std::size_t k = 1; k < K; ++k) {
    const Fitted& f = fits[k];
    const bool diffusion = f.method == SuspectMethod::DiffusionTerms;
    std::vector<double> gain;
    double total = 0.0;
    bool invalid = false;
    for (const auto& s : sums) {
      const double g = diffusion ? s.loglik[k] - s.loglik[0] : s.contrast[0] - s.contrast[k];
      invalid = invalid || (diffusion && s.invalid_variance);
      gain.push_back(g);
      total += g;
    }
    Suspect sp;
    sp.effect = f.name;
    sp.scale = diffusion ? "diffusion likelihood" : f.method == SuspectMethod::DynamicForce ? "drift contrast (dynamic force)"
                 : f.method == SuspectMethod::ColoredExcitation ? "drift contrast (predicted OU excitation)"
                                                                 : "drift contrast";
    sp.evidence = total;
    sp.z = block_z(gain);
    if (invalid) {
      sp.evidence = -std::numeric_limits<double>::infinity();
      sp.z = 0.0;
    }
    sp.held_out_significant = sp.z > options.z_threshold && sp.evidence > 0.0;
    sp.significant = sp.held_out_significant;
    if (f.method == SuspectMethod::DynamicForce || f.method == SuspectMethod::ColoredExcitation) {
      if (const Effect* fe = f.model.find_effect(f.effect.id)) {
        for (const auto& [key, val] : fe->params) sp.params[key] = val;
        for (const auto& [key, val] : fe->stderr_) sp.params_stderr[key] = val;
      }
    } else if (f.user) {
      const UserEffectFit uf = user_effect_fit(f.model, *f.user);
      sp.params = uf.params;
      sp.params_stderr = uf.stderr_;
    } else {
      const auto ep = identify::effect_parameters(f.model, {f.effect});
      if (!ep.empty()) {
        sp.params = ep[0].params;
        sp.params_stderr = ep[0].stderr_;
      }
    }
    if (!f.user) sp.outside_domain = effect_domain_violation(Effect{f.effect.id, sp.params, {}});
    if (!sp.outside_domain.empty()) sp.held_out_significant = sp.significant = false;
    sp.block_gain = gain;
    sp.terms = f.added;
    rep.ranked.push_back(std::move(sp));
  }
  std::stable_sort(rep.ranked.begin(), rep.ranked.end(),
                   [](const Suspect& a, const Suspect& b) { return a.evidence > b.evidence; });
  return rep;
}

}  // namespace vehs::diagnose

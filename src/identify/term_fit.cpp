#include "term_fit.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "diffusion_pass.hpp"
#include "estimator_choice.hpp"
#include "drift_pass.hpp"
#include "lens_mask.hpp"
#include "pilot.hpp"
#include "positive_diffusion.hpp"
#include "standard_errors.hpp"
#include "vehs/core/dominant_frequency.hpp"
#include "vehs/core/quantisation.hpp"
#include "vehs/core/error.hpp"

namespace vehs::identify::detail {

namespace {

using Eigen::VectorXd;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr std::size_t kMinRecordSamples = 16;

// ---------------------------------------------------------------------------- dictionaries

/// The libraries plus the terms of the requested term-like effects, which the selection keeps.
struct Dictionaries {
  Dictionary phi, psi;
  std::vector<bool> keep_phi, keep_psi;
  std::vector<std::string> phi_names, psi_names;
};

std::vector<Term> merged_terms(std::vector<Term> lib, const std::vector<Term>& add) {
  for (const auto& t : add)
    if (std::find(lib.begin(), lib.end(), t) == lib.end()) lib.push_back(t);
  std::sort(lib.begin(), lib.end());
  return lib;
}

std::vector<bool> keep_mask(const Dictionary& d, const std::vector<Term>& keep) {
  std::vector<bool> m(static_cast<std::size_t>(d.size()), false);
  for (int k = 0; k < d.size(); ++k)
    m[static_cast<std::size_t>(k)] = std::find(keep.begin(), keep.end(), d.term(k)) != keep.end();
  return m;
}

std::vector<std::string> term_names(const Dictionary& d) {
  std::vector<std::string> n;
  for (int k = 0; k < d.size(); ++k) n.push_back(d.name(k));
  return n;
}

Dictionaries make_dictionaries(const Options& options) {
  std::vector<Term> effect_drift, effect_diffusion;
  for (const auto& e : options.effects) {
    const EffectTerms t = unit_effect_terms(e.id);
    for (const auto& tc : t.drift) effect_drift.push_back(tc.term);
    for (const auto& tc : t.diffusion) effect_diffusion.push_back(tc.term);
  }
  Dictionaries d;
  d.phi = Dictionary(merged_terms(options.drift_library, effect_drift));
  d.psi = Dictionary(merged_terms(options.diffusion_library, effect_diffusion));
  std::vector<Term> keep_d = options.keep_drift, keep_q = options.keep_diffusion;
  keep_d.insert(keep_d.end(), effect_drift.begin(), effect_drift.end());
  keep_q.insert(keep_q.end(), effect_diffusion.begin(), effect_diffusion.end());
  d.keep_phi = keep_mask(d.phi, keep_d);
  d.keep_psi = keep_mask(d.psi, keep_q);
  d.phi_names = term_names(d.phi);
  d.psi_names = term_names(d.psi);
  return d;
}

// ------------------------------------------------------------------- estimator and stride


/// What the pilots read from the data.
struct PilotInputs {
  const Dataset& data;
  const Dictionaries& dict;
  double dt;
  std::size_t pilot_rows;
  const double* known;
  std::size_t min_size;  ///< samples of the shortest record
  double omega_dt;       ///< the data's ω̂Δt (vehs/core/dominant_frequency.hpp)
  Quantisation quant;    ///< the grid of quantised values (vehs/core/quantisation.hpp)

  bool too_short(int k) const { return min_size < 4 * static_cast<std::size_t>(k) + kMinRecordSamples; }
  Pilot run(int k, Target target, bool central = true) const {
    return run_pilot(data, dict.phi, dict.psi, Kinematics(central, k, dt), target, pilot_rows, known);
  }
};

/// The noisy estimator's stride: the noise share η_k = 6 (ρ_2k − ρ_3k) of â's variance falls with
/// the stride as 1/(1 + α h³) (process part ∝ 1/h, noise part ∝ 1/h⁴): double k until η_k is
/// below the goal by 4 of its standard errors (6√2/√rows, as in sampling_rule; on short pilots
/// at least below half the goal), then solve for
/// the stride with η = goal from that pilot. Stopping at the first η_k < goal let an estimate
/// that fell below the goal by its own noise (η_k ≈ 1 − 1e-3 at small strides, sd ≈ 0.02 on the
/// pilot's 2.5·10⁵ rows) end the search at stride 1–4, at 1 or 2 with a fit that is all noise
/// (issue 11: 10 of 62 seeds of tests/identify's white-sensor-noise case; now 0 of 100, every
/// stride 5 or 6); at the stride where η_k is clearly below the goal, 1 − η_k is resolved and
/// the cube-root solve is stable.
Pilot noisy_stride_pilot(const PilotInputs& in, Pilot pilot, double goal) {
  auto share = [](const Pilot& pl) { return std::clamp(pl.noise_share, 1e-6, 1.0 - 1e-6); };
  auto resolved_below_goal = [&](const Pilot& pl) {
    return share(pl) < std::max(goal - 4.0 * 6.0 * std::sqrt(2.0 / std::max(pl.rows, 1.0)), 0.5 * goal);
  };
  // never below the dither stride of values on a grid (their rounding is white only from there:
  // "%.1f" values of a Duffing of sd 0.4 at 1 kHz, dither stride 256, a noise share read as 0
  // there, were solved down to stride 1 and written as x −226, 2D 13 980 for −1, 0.09)
  const int lowest = in.quant.quantised() ? std::max(1, std::min(pilot.k, in.quant.dither_stride)) : 1;
  int guard = 0;
  while (!resolved_below_goal(pilot) && !in.too_short(2 * pilot.k) && guard++ < 20)
    pilot = in.run(2 * pilot.k, Target::Noisy);
  const double eta = share(pilot);
  if (eta < goal && pilot.k > lowest) {
    const double ratio = ((1.0 - goal) / goal) / ((1.0 - eta) / eta);  // (h*/h)³
    const int next = std::clamp(static_cast<int>(std::lround(pilot.k * std::cbrt(ratio))), lowest, pilot.k);
    if (next != pilot.k) pilot = in.run(next, Target::Noisy);
  }
  return pilot;
}

/// The stride at which the sampling rule can read the data: when the reading at the start
/// stride is unexplained (sampling_unexplained, core/fit_info.hpp), the stride doubles until a
/// reading explains the data; the start pilot when none does before the records run short.
/// Integer ADC counts at 10 kHz (a Duffing at ω·Δt 0.004, 90 % of consecutive samples equal):
/// lag-1 autocorrelation −0.50 at stride 1; at stride 4 white noise's signature (ρ_k −0.66,
/// ρ_2k +0.17): the quantisation error is a staircase correlated over a few samples, white on
/// longer strides, and the noisy estimator's stride search goes on from there.
Pilot explained_stride_pilot(const PilotInputs& in, const Pilot& start) {
  auto unexplained = [&](const Pilot& pl) {
    const SamplingRule rule = sampling_rule(pl.rho_k, pl.rho_2k, pl.rho_3k, pl.rows);
    return sampling_unexplained(rule.verdict, pl.rho_k, pl.rho_3k, in.omega_dt * pl.k);
  };
  Pilot pilot = start;
  int guard = 0;
  while (unexplained(pilot) && !in.too_short(2 * pilot.k) && guard++ < 20) pilot = in.run(2 * pilot.k, Target::Uli);
  return unexplained(pilot) || in.omega_dt * pilot.k >= 0.2 ? start : pilot;
}

// ----------------------------------------------------------------------- the diffusion pass

/// Rows per batch of the batch-means covariance: long against the residual correlation range,
/// and at least ~30 batches per estimated parameter (a multiple of the feature block). A given
/// se_block must be a feature block or more and leave 30 batches, none longer than a fold.
int score_batch_rows(const Options& options, bool central, int k, std::size_t rows, std::size_t params) {
  const std::size_t corr_len = central ? 3 * static_cast<std::size_t>(k) : 2;
  params = std::max<std::size_t>(1, params);
  const std::size_t block = kBlockRows, most = rows / std::max<std::size_t>(30, static_cast<std::size_t>(options.folds));
  if (options.se_block > 0 && (options.se_block < block || options.se_block > most))
    throw Error("se_block = " + std::to_string(options.se_block) + " is outside its range for these data: 0 (automatic)" +
                (most < block ? std::string() : " or " + std::to_string(block) + " to " + std::to_string(most)) +
                " rows (at least one feature block of " + std::to_string(block) + " rows, at most the " +
                std::to_string(rows) + " rows fitted / max(30 batches, folds))");
  std::size_t L = options.se_block > 0 ? options.se_block : std::max<std::size_t>(1024, 50 * corr_len);
  if (options.se_block == 0 && rows / L < 30 * params)
    L = std::max<std::size_t>(10 * corr_len + 10, rows / (30 * params));
  return static_cast<int>(std::max<std::size_t>(1, (L + kBlockRows / 2) / kBlockRows) * kBlockRows);
}

DiffusionSetup diffusion_setup(const Pilot& pilot, const DriftModel& dm, Estimator est, int k) {
  const bool central = uses_central_kinematics(est);
  DiffusionSetup ds;
  ds.target = target_of(est);
  ds.dm = dm;
  ds.w = diffusion_weights(pilot);
  ds.w.weighted = est != Estimator::Paper;
  ds.lags = {1, 2, 3};
  if (k > 3) ds.lags.push_back(k);
  ds.lags.push_back(2 * k);
  ds.lags.push_back(3 * k);  // the sensor-noise covariance is C(2k) − C(3k) (see sampling_rule)
  ds.scores = true;
  ds.ito = central;
  ds.noise = est == Estimator::Noisy;
  return ds;
}

/// The sensor-noise variance s² = (C(2k) − C(3k))·h⁴ and the drift corrections it implies.
double set_sensor_noise(double C2k_minus_C3k, double h, DriftCorrection& corr) {
  const double s2 = std::max(C2k_minus_C3k, 0.0) * h * h * h * h;
  corr.var_v_noise = s2 / (2.0 * h * h);
  corr.ax_cov = 2.0 * s2 / (h * h);
  return s2;
}

QuadraticStats total_of(const std::vector<QuadraticStats>& v) {
  QuadraticStats t = v[0];
  for (std::size_t i = 1; i < v.size(); ++i) t += v[i];
  return t;
}

std::vector<QuadraticStats> drift_folds(const std::vector<DriftStats>& stats, const Dictionary& phi,
                                        const DriftCorrection& corr) {
  std::vector<QuadraticStats> v;
  for (const auto& s : stats) v.push_back(drift_quadratic(s, phi, corr));
  return v;
}

const SupportFit& chosen_fit(const SelectionResult& s) { return s.path[static_cast<std::size_t>(s.chosen)]; }

ResidualReport residual_report(const ResidualMoments& m, const DiffusionSetup& ds, const Pilot& pilot) {
  ResidualReport rr;
  rr.rows = m.n;
  rr.rms = std::sqrt(m.r2 / std::max(m.n, 1.0));
  if (m.r2 > 0.0 && m.n > 0.0) rr.kurtosis_factor = m.r4 * m.n / (3.0 * m.r2 * m.r2);
  for (std::size_t l = 0; l < ds.lags.size(); ++l) rr.autocorrelation.emplace_back(ds.lags[l], m.autocorrelation(l));
  rr.expected_lag_k = ds.target == Target::Uli ? 0.25 : ds.target == Target::Noisy ? kNaN : 0.0;
  rr.long_run_factor_drift = pilot.drift_lr;
  rr.long_run_factor_diffusion = pilot.diffusion_lr;
  return rr;
}

void add_terms(TermList& list, std::map<std::string, double>& stderr_, const Dictionary& d,
               const std::vector<int>& support, const VectorXd& coef, const VectorXd& se, int se_offset,
               const std::string& what) {
  for (std::size_t i = 0; i < support.size(); ++i) {
    const int t = support[i];
    list.push_back({d.term(t), coef[t]});
    stderr_[d.name(t)] = se[se_offset + static_cast<int>(i)];
  }
  canonicalize(list, what);
}

/// The sandwich with the model file's parameter names (drift on S, then diffusion on T).
ParameterCovariance named_covariance(const Dictionary& phi, const std::vector<int>& S, const Dictionary& psi,
                                     const std::vector<int>& T, const Eigen::MatrixXd& cov) {
  ParameterCovariance c;
  for (int t : S) c.names.push_back("drift[" + phi.name(t) + "]");
  for (int t : T) c.names.push_back("diffusion[" + psi.name(t) + "]");
  if (cov.rows() != static_cast<Eigen::Index>(c.names.size())) return {};
  c.matrix.resize(c.names.size() * c.names.size());
  for (std::size_t i = 0; i < c.names.size(); ++i)
    for (std::size_t j = 0; j < c.names.size(); ++j)
      c(i, j) = cov(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
  return c;
}

// ------------------------------------------------------------------------------- the stages

/// How the data were sampled and what that decides: the estimator, the stride, and the pilot in
/// the final kinematics (weights of the diffusion fit, Itô correction for the drift selection,
/// long-run variance factors of the BIC).
struct SamplingStage {
  Pilot diag;  ///< at stride 1 (or the requested stride): the sampling diagnosis
  EstimatorDecision decision;
  Pilot pilot;
  int k = 1;
  double known_s2 = 0.0;  ///< white noise of known variance on x at stride k (quantisation), else 0
};

/// Quantised values (vehs/core/quantisation.hpp): the rounding's white noise q²/12, known, at a
/// stride where it is white (central kinematics only); the reason says so.
void add_quantisation_noise(SamplingStage& st, const Quantisation& quant, Estimator est) {
  if (!quant.quantised() || !uses_central_kinematics(est) || st.k < quant.dither_stride) return;
  st.known_s2 = quant.noise_variance();
  st.decision.reason += "; the values lie on a grid (sampling.quantisation_step): its rounding noise, white from stride " +
                        std::to_string(quant.dither_stride) + ", corrected";
}

SamplingStage sampling_stage(const PilotInputs& in, const Options& options) {
  SamplingStage st;
  // quantised values at a fast rate: the rounding error is white only from the dither stride
  const bool central_request = options.estimator == Estimator::Auto || uses_central_kinematics(options.estimator);
  int k = options.stride > 0 ? options.stride : central_request ? in.quant.dither_stride : 1;
  while (options.stride == 0 && k > 1 && in.too_short(k)) k /= 2;  // records too short for that stride
  if (in.too_short(k))
    throw Error("records are too short for stride " + std::to_string(k) + " (the shortest has " +
                std::to_string(in.min_size) + " samples, " +
                std::to_string(4 * k + static_cast<int>(kMinRecordSamples)) + " needed)");
  st.diag = in.run(k, options.estimator == Estimator::Noisy ? Target::Noisy : Target::Uli);
  if (options.estimator == Estimator::Auto && options.stride == 0) st.diag = explained_stride_pilot(in, st.diag);
  st.decision = choose_estimator(st.diag, options.estimator, in.omega_dt * st.diag.k,
                                 rounding_share(st.diag, in.quant, in.dt), in.quant.step, double(in.data.x.size()));
  const Estimator est = st.decision.estimator;
  const Target target = target_of(est);
  const bool central = uses_central_kinematics(est);
  st.pilot = st.diag;
  if (est == Estimator::Noisy && options.stride == 0)
    st.pilot = noisy_stride_pilot(in, st.pilot, options.noise_share_target);
  st.k = central ? st.pilot.k : 1;
  if (!(st.pilot.central == central && st.pilot.k == st.k && st.pilot.target == target))
    st.pilot = in.run(st.k, target, central);
  const Kinematics kin(central, st.k, in.dt);
  finish_pilot(st.pilot, in.data, in.dict.phi, in.dict.psi, kin, in.known);
  add_quantisation_noise(st, in.quant, est);
  return st;
}

/// The drift selection from the per-fold drift statistics (Itô correction from the pilot's
/// diffusion; the noisy estimator's sensor-noise corrections from the pilot's covariances).
struct DriftSelection {
  DriftStats total;
  DriftCorrection corr;
  double s2 = 0.0;  ///< sensor-noise variance (noisy estimator)
  std::vector<int> support;
};

DriftSelection select_drift(const std::vector<DriftStats>& folds, const Dictionaries& dict, const Pilot& pilot,
                            Estimator est, double h, double known_s2, SelectionOptions selection, Report& rep) {
  DriftSelection d;
  d.total = folds[0];
  for (std::size_t f = 1; f < folds.size(); ++f) d.total.add(folds[f]);
  const int P = dict.phi.size();
  rep.fit.rows = static_cast<std::size_t>(d.total.n);
  rep.fit.rows_left_out = static_cast<std::size_t>(d.total.left_out);
  rep.fit.drift_condition_full =
      require_well_conditioned(d.total.Gaug.topLeftCorner(P, P), full_support(P), dict.phi_names, "the drift dictionary");
  d.corr.ito = uses_central_kinematics(est);
  d.corr.q = pilot.q;
  const double known_c = known_s2 / (h * h * h * h);  // its C(2k) − C(3k)
  if (est == Estimator::Noisy) d.s2 = set_sensor_noise(std::max(pilot.C2k - pilot.C3k, known_c), h, d.corr);
  else if (known_s2 > 0.0) d.s2 = set_sensor_noise(known_c, h, d.corr);
  rep.drift_selection.dictionary = dict.phi.terms();
  selection.variance_factor = pilot.drift_lr;
  rep.drift_selection.selection = select_sparse(drift_folds(folds, dict.phi, d.corr), full_support(P), dict.keep_phi, selection);
  d.support = chosen_fit(rep.drift_selection.selection).support;
  return d;
}

/// The diffusion selection from the per-fold residual statistics (the noisy estimator's sensor
/// noise re-estimated from the drift residuals' covariances, updating `drift.corr`).
struct DiffusionSelection {
  ResidualMoments residuals;
  QuadraticStats total;
  std::vector<int> support;
  VectorXd q;
};

DiffusionSelection select_diffusion(const std::vector<DiffusionStats>& folds, const DiffusionSetup& ds,
                                    const Dictionaries& dict, const Pilot& pilot, Estimator est, double h,
                                    double known_s2, SelectionOptions selection, DriftSelection& drift, Report& rep,
                                    FitInfo& fit, const ResidualMoments* standardized, const StateBox& box) {
  DiffusionSelection q;
  q.residuals = folds[0].mom;
  for (std::size_t f = 1; f < folds.size(); ++f) q.residuals.add(folds[f].mom);
  if (est == Estimator::Noisy) {
    const std::size_t L = ds.lags.size();
    const ResidualMoments& m = standardized ? *standardized : q.residuals;
    const double c = m.white_autocovariance(L - 2) - m.white_autocovariance(L - 1);
    drift.s2 = set_sensor_noise(std::max(c, known_s2 / (h * h * h * h)), h, drift.corr);
  }
  fit.sampling.sensor_noise_sd = std::sqrt(drift.s2);
  std::vector<QuadraticStats> qfolds;
  for (const auto& s : folds) qfolds.push_back(s.quadratic());
  q.total = total_of(qfolds);
  const std::vector<int> all = full_support(dict.psi.size());
  rep.fit.diffusion_condition_full = require_well_conditioned(q.total.G, all, dict.psi_names, "the diffusion dictionary");
  rep.diffusion_selection.dictionary = dict.psi.terms();
  selection.variance_factor = pilot.diffusion_lr;
  rep.diffusion_selection.selection = select_sparse(qfolds, all, dict.keep_psi, selection);
  positive_step(rep.diffusion_selection.selection, q.total, dict.psi, dict.keep_psi, box);
  const SupportFit& chosen = chosen_fit(rep.diffusion_selection.selection);
  q.support = chosen.support;
  q.q = full_coefficients(chosen, dict.psi.size());
  return q;
}

/// The drift refitted with the final diffusion (Itô correction) and noise level, the standard
/// errors at the final (q, s²), and the model's terms.
void finish_terms(const std::vector<DiffusionStats>& qfolds, const DiffusionSetup& ds, const Dictionaries& dict,
                  const std::vector<DriftStats>& dfolds, DriftSelection& drift, const DiffusionSelection& diffusion,
                  Result& res) {
  const Dictionary& phi = dict.phi;
  drift.corr.q = diffusion.q;
  const QuadraticStats drift_total = total_of(drift_folds(dfolds, phi, drift.corr));
  const std::vector<int>& S = drift.support;
  const SupportFit cfit = fit_support(drift_total, S);
  const VectorXd c = full_coefficients(cfit, phi.size());
  const ScoreSums sums = score_sums(qfolds);
  Eigen::MatrixXd cov;
  const VectorXd se = term_standard_errors(sums, ds, phi, dict.psi.size(), S, diffusion.support, diffusion.q, drift.s2,
                                           drift_total.G, drift.total.ito, drift.corr.ito, diffusion.total.G, &cov);
  Model& m = res.model;
  m.covariance = named_covariance(phi, S, dict.psi, diffusion.support, cov);
  add_terms(m.drift, m.drift_stderr, phi, S, c, se, 0, "identified drift");
  add_terms(m.diffusion, m.diffusion_stderr, dict.psi, diffusion.support, diffusion.q, se, static_cast<int>(S.size()),
            "identified diffusion");
  res.report.fit.drift_condition_selected = cfit.condition;
  res.report.fit.stderr_batches = sums.batches;
  res.report.fit.stderr_batch_rows = ds.block_rows;
}

/// sign(y) as the tent-averaged acceleration of central kinematics sees it (smoothed_sign.hpp):
/// a22 from the pilot's diffusion, the noisy estimator's white noise in v̂.
void set_sign_smoothing(Dictionaries& dict, const Pilot& pilot, Estimator est, double h) {
  TermList a22;
  for (int j = 0; j < dict.psi.size(); ++j) a22.push_back({dict.psi.term(j), pilot.q[j]});
  const double var_v_noise = est == Estimator::Noisy ? std::max(pilot.C2k - pilot.C3k, 0.0) * h * h / 2.0 : 0.0;
  dict.phi.set_sign_smoothing(h, a22, diffusion_weights(pilot).floor, var_v_noise);
}

std::size_t shortest_record(const Dataset& data) {
  std::size_t n = data.records.front().size;
  for (const auto& r : data.records) n = std::min(n, r.size);
  return n;
}

}  // namespace

namespace {

Result identify_terms_once(const Dataset& data, const Options& options) {
  const auto t_start = std::chrono::steady_clock::now();
  const double* known = options.known_force ? options.known_force->data() : nullptr;
  Dictionaries dict = make_dictionaries(options);
  Result res;
  FitInfo& fit = res.model.fit.emplace();
  Report& rep = res.report;
  auto lap = [&, t = std::chrono::steady_clock::now()](const char* what) mutable {
    const auto now = std::chrono::steady_clock::now();
    rep.fit.timings.emplace_back(what, std::chrono::duration<double>(now - t).count());
    t = now;
  };

  require(!data.records.empty(), "no records to identify from");
  if (dict.phi.uses_u()) require(data.has_u(), "the drift library has the term 'u' but the data have no drive column u");
  RecordChecks checks;
  checks.min_samples = kMinRecordSamples;
  checks.varying_x = true;
  check_records(data, checks);
  lap("validate");

  const double dt = data.common_dt();
  const SamplingStage sampling = sampling_stage(
      {data, dict, dt, options.pilot_samples, known, shortest_record(data), dominant_omega_dt(data), find_quantisation(data)},
      options);
  lap("pilot");
  const Pilot& pilot = sampling.pilot;
  const Pilot& diag = sampling.diag;
  const Estimator est = sampling.decision.estimator;
  const bool central = uses_central_kinematics(est);
  const int k = sampling.k;
  const Kinematics kin(central, k, dt);
  dict.phi.set_sign_kernel_halfwidth(std::max(0.05 * pilot.v_sd, 1e-300));
  if (central) set_sign_smoothing(dict, pilot, est, kin.h);
  fit.estimator = est;
  fit.stride = k;
  fit.sampling = {dt,          diag.k, diag.rho_1, diag.rho_k, diag.rho_2k, diag.rho_3k, diag.noise_share,
                  sampling.decision.verdict, 0.0, sampling.known_s2 > 0.0 ? std::sqrt(12.0 * sampling.known_s2) : 0.0};

  const SsrRule rule = options.ssr_rule_set ? options.ssr_rule : est == Estimator::Paper ? SsrRule::AbsCoef : SsrRule::TRatio;
  const SelectionOptions selection{options.sparsity, rule, options.criterion, options.stlsq_threshold, 1.0};
  Context cx{data, dict.phi, dict.psi, kin};
  cx.known = known;
  const FourthDerivative jerk(dict.phi.terms(), pilot.c, kin.h);
  const bool h2_correction = central && options.discretization_correction;
  if (h2_correction) cx.jerk = &jerk;
  const int F = options.folds;
  const auto spans = make_spans(data, kin, F, 0);
  vehs::detail::ProgressCounter progress(options.progress, "identify", 2 * static_cast<long long>(spans.size()));

  // pass 1: drift statistics per fold, drift selection. A state-dependent diffusion: the rows
  // where the lens does not hold under the pilot's (masked) drift are left out of both passes, as
  // out of the pilot's fits and the sampling rule (lens_mask.hpp; a y² diffusion's bursts into a
  // stiff wall pulled β 40×)
  if (central && pilot.masked) cx.lens = &pilot.lens;
  const bool noise_moments = est == Estimator::Noisy || sampling.known_s2 > 0.0;
  auto dstats = drift_pass(cx, central, noise_moments, spans, F, &progress);
  if (cx.lens) {
    double kept = 0.0, left_out = 0.0;
    for (const auto& s : dstats) kept += s.n, left_out += s.left_out;
    if (!mask_holds(kept, kept + left_out)) cx.lens = nullptr, dstats = drift_pass(cx, central, noise_moments, spans, F, nullptr);
  }
  lap("drift_pass");
  DriftSelection drift = select_drift(dstats, dict, pilot, est, kin.h, sampling.known_s2, selection, rep);

  // pass 2: residuals of the selected drift -> weighted diffusion statistics per fold, selection
  const VectorXd c = full_coefficients(chosen_fit(rep.drift_selection.selection), dict.phi.size());
  DiffusionSetup ds = diffusion_setup(pilot, drift_model(dict.phi, drift.support, c), est, k);
  if (est == Estimator::Uli) ds.uli_noise = 9.0 * sampling.known_s2 / (kin.h * kin.h * kin.h);
  ds.block_rows = score_batch_rows(options, central, k, rep.fit.rows,
                                   drift.support.size() + static_cast<std::size_t>(dict.psi.size()));
  const auto qstats = diffusion_pass(cx, ds, spans, F, &progress);
  lap("diffusion_pass");
  // the sensor noise of a state-dependent diffusion from the standardized residuals (as the pilot)
  std::optional<ResidualMoments> standardized;
  if (est == Estimator::Noisy && state_dependent(dict.psi)) standardized = standardized_moments(cx, ds, ds.w, spans);
  const DiffusionSelection diffusion =
      select_diffusion(qstats, ds, dict, pilot, est, kin.h, sampling.known_s2, selection, drift, rep, fit,
                       standardized ? &*standardized : nullptr, state_box(data, pilot.v_sd));

  progress.finish();
  finish_terms(qstats, ds, dict, dstats, drift, diffusion, res);
  rep.estimator = {options.estimator, sampling.decision.reason, h2_correction, rule, sampling.decision.unexplained};
  rep.residuals = residual_report(diffusion.residuals, ds, pilot);
  rep.sparsity = options.sparsity;
  rep.criterion = options.criterion;
  rep.folds = F;
  if (!options.effects.empty()) rep.effect_params = effect_parameters(res.model, options.effects);
  rep.fit.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  return res;
}


}  // namespace

Result identify_terms(const Dataset& data, const Options& options) {
  Result r = identify_terms_once(data, options);
  const double eta = residual_noise_share(r, options);
  if (!(std::isfinite(eta) && residual_noise_matters(eta, r.report.residuals))) return r;
  Options noisy = options;
  noisy.estimator = Estimator::Noisy;
  Result n = identify_terms_once(data, noisy);
  n.report.estimator.requested = Estimator::Auto;
  n.report.estimator.reason = r.report.estimator.reason + residual_noise_reason(r.report.residuals, eta);
  return n;
}

}  // namespace vehs::identify::detail

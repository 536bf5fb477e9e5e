#include "vehs/likelihood/refine.hpp"

#include <ceres/ceres.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "vehs/core/error.hpp"
#include "vehs/likelihood/detail/bias_correction.hpp"
#include "vehs/likelihood/detail/data_scales.hpp"
#include "vehs/likelihood/detail/data_share.hpp"
#include "vehs/likelihood/detail/domain.hpp"
#include "vehs/likelihood/detail/evaluator.hpp"
#include "vehs/likelihood/detail/hidden_state_starts.hpp"
#include "vehs/likelihood/detail/measurement_noise_start.hpp"
#include "vehs/likelihood/detail/phase_scan.hpp"
#include "vehs/likelihood/detail/record_phase_bias.hpp"
#include "vehs/likelihood/detail/selection.hpp"

namespace vehs::likelihood {

using detail::Derivatives;
using detail::EvaluationFailure;
using detail::Evaluator;
using detail::Parameterization;

bool RefineOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (const std::string why = filter.invalid_reason(); !why.empty()) return fail(why);
  if (!(measurement_sd_start >= 0.0)) return fail("measurement_sd_start must be >= 0");
  if (!(lr_alpha > 0.0 && lr_alpha < 0.5)) return fail("lr_alpha must be in (0, 0.5)");
  if (max_iterations < 1) return fail("max_iterations must be >= 1");
  if (max_rounds < 1) return fail("max_rounds must be >= 1");
  if (max_added < 0) return fail("max_added must be >= 0");
  if (!(screen_samples >= 1000.0)) return fail("screen_samples must be >= 1000");
  if (!(step_tolerance > 0.0)) return fail("step_tolerance must be > 0");
  if (warm_start_samples < 1000) return fail("warm_start_samples must be >= 1000");
  if (bias_correction_datasets < 0 || bias_correction_datasets > 1000)
    return fail("bias_correction_datasets must be in [0, 1000]");
  if (bias_correction_datasets > 0 && per_record_phase && !bias_correction_auto)
    return fail("bias_correction_datasets needs one shared harmonic phase (per_record_phase false): the simulator "
                "has one phase");
  return true;
}

int Result::find(const std::string& name) const {
  for (std::size_t i = 0; i < parameters.size(); ++i)
    if (parameters[i].name == name) return int(i);
  return -1;
}

std::string Summary::BriefReport() const {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "likelihood: %s, log L %.6g -> %.6g, %d rounds, %d iterations, %d gradients, "
                "Newton step %.2g SE, %.3g s",
                converged ? "converged" : "NOT converged", initial_log_likelihood,
                final_log_likelihood, rounds, iterations, gradient_evaluations, newton_step_se,
                seconds);
  return buf;
}

std::string Summary::FullReport() const {
  std::ostringstream os;
  os << BriefReport() << "\n"
     << "  observations " << observations << " in " << blocks << " blocks, " << parameters
     << " parameters, " << substeps << " RK4 substeps per interval, " << threads << " threads\n"
     << "  covariance: " << covariance << "\n  last Ceres message: " << message << "\n";
  for (const auto& s : selection) {
    const bool add = !s.added.empty();
    os << "  selection: " << (add ? "add " + s.added : "remove " + s.removed) << " (|z| " << s.z << "): 2 dlogL "
       << s.delta << (s.by_wald ? " (Wald z^2, no refit)" : "") << ((s.delta < s.threshold) ? " < " : " >= ") << s.threshold
       << (add ? (s.accepted ? " added" : " not added") : (s.accepted ? " removed" : " kept"));
    if (s.together > 1) os << " (" << s.together << " terms in one refit)";
    os << "\n";
  }
  if (bias_correction_datasets > 0)
    os << "  bias correction: " << bias_correction_datasets << " simulated data sets, largest shift "
       << bias_correction_max_se << " SE (covariance x " << 1.0 + 1.0 / bias_correction_datasets << "), seed "
       << bias_correction_seed << "\n";
  if (!bias_correction_skipped.empty()) os << "  bias correction skipped: " << bias_correction_skipped << "\n";
  return os.str();
}

namespace {

using Clock = std::chrono::steady_clock;

/// −log L in whitened coordinates θ = θ₀ + W z, offset so that the cost stays positive.
class WhitenedObjective final : public ceres::FirstOrderFunction {
 public:
  WhitenedObjective(const Evaluator& ev, const Eigen::VectorXd& theta0, const Eigen::MatrixXd& W,
                    double offset, int& values, int& gradients)
      : ev_(ev), theta0_(theta0), W_(W), offset_(offset), values_(values), gradients_(gradients) {}

  bool Evaluate(const double* z, double* cost, double* gradient) const override {
    const Eigen::VectorXd theta =
        theta0_ + W_ * Eigen::Map<const Eigen::VectorXd>(z, W_.cols());
    if (!theta.allFinite()) return false;
    if (gradient) {
      ++gradients_;
      Derivatives d;
      if (!ev_.derivatives(theta.data(), d, false, false, nullptr)) return false;
      *cost = offset_ - d.log_likelihood;
      Eigen::Map<Eigen::VectorXd>(gradient, W_.cols()) = -(W_.transpose() * d.gradient);
      return true;
    }
    ++values_;
    double ll = 0.0;
    if (!ev_.value(theta.data(), ll, nullptr)) return false;
    *cost = offset_ - ll;
    return true;
  }
  int NumParameters() const override { return int(W_.cols()); }

 private:
  const Evaluator& ev_;
  Eigen::VectorXd theta0_;
  Eigen::MatrixXd W_;
  double offset_;
  int& values_;
  int& gradients_;
};

/// W with W Wᵀ = F_reg⁻¹ (F regularised so that a unit step never moves a log-scale parameter
/// or a phase by more than 1, and so that an unidentified direction cannot blow up).
Eigen::MatrixXd whitening(const Parameterization& p, const Eigen::MatrixXd& F,
                          const std::string& where) {
  const Eigen::Index n = F.rows();
  Eigen::MatrixXd R = 0.5 * (F + F.transpose());
  for (Eigen::Index i = 0; i < n; ++i) {
    const ParameterInfo& info = p.parameters()[std::size_t(i)];
    const double d = R(i, i);
    if (!(d > 0.0) || !std::isfinite(d))
      throw Error(where + ": parameter " + info.name + " does not influence the likelihood "
                  "(zero Fisher information); remove it or hold it fixed");
    const bool bounded = info.log_scale || info.kind == ParameterKind::RecordPhase;
    R(i, i) += std::max(1e-10 * d, bounded ? 1.0 : 0.0);
  }
  Eigen::LLT<Eigen::MatrixXd> llt(R);
  if (llt.info() != Eigen::Success) {
    // fall back to the diagonal (strongly collinear parameters)
    Eigen::MatrixXd W = Eigen::MatrixXd::Zero(n, n);
    for (Eigen::Index i = 0; i < n; ++i) W(i, i) = 1.0 / std::sqrt(R(i, i));
    return W;
  }
  // F = L Lᵀ → W = L⁻ᵀ
  Eigen::MatrixXd Linv = llt.matrixL().solve(Eigen::MatrixXd::Identity(n, n));
  return Linv.transpose();
}

struct FitState {
  Eigen::VectorXd theta;
  Derivatives d;  ///< at theta, with Fisher
  Eigen::MatrixXd W;
  double step_se = 0.0;
};

double newton_step_se(const Eigen::MatrixXd& W, const Eigen::VectorXd& g) {
  return (W.transpose() * g).norm();
}

Derivatives derivatives_or_throw(const Evaluator& ev, const Eigen::VectorXd& theta, bool batches,
                                 const char* when) {
  Derivatives d;
  EvaluationFailure f;
  if (!ev.derivatives(theta.data(), d, true, batches, &f))
    throw FilterDiverged(ev.message(f) + std::string(" (") + when + ")");
  return d;
}

/// Rounds of whitened BFGS until the Newton step is below the tolerance.
FitState maximise(const Evaluator& ev, Eigen::VectorXd theta, const RefineOptions& o,
                  Summary& s, const std::string& where) {
  const Parameterization& p = ev.parameterization();
  FitState st;
  st.theta = std::move(theta);
  st.d = derivatives_or_throw(ev, st.theta, false, "at the start values");
  ++s.gradient_evaluations;
  for (int round = 0; round < o.max_rounds; ++round) {
    st.W = whitening(p, st.d.fisher, where);
    st.step_se = newton_step_se(st.W, st.d.gradient);
    if (st.step_se < o.step_tolerance) {
      s.converged = true;
      break;
    }
    ++s.rounds;
    const double offset = st.d.log_likelihood + double(ev.observations()) + 1.0;
    auto* fn = new WhitenedObjective(ev, st.theta, st.W, offset, s.value_evaluations,
                                     s.gradient_evaluations);
    ceres::GradientProblem problem(fn);
    ceres::GradientProblemSolver::Options co;
    co.line_search_direction_type = ceres::BFGS;
    co.max_num_iterations = o.max_iterations;
    co.function_tolerance = 1e-7 / double(ev.observations() + 1);
    co.gradient_tolerance = 0.1 * o.step_tolerance;
    co.parameter_tolerance = 1e-10;
    co.logging_type = ceres::SILENT;
    std::vector<double> z(std::size_t(st.W.cols()), 0.0);
    ceres::GradientProblemSolver::Summary cs;
    ceres::Solve(co, problem, z.data(), &cs);
    s.iterations += int(cs.iterations.size());
    s.message = cs.message;
    const Eigen::VectorXd next =
        st.theta + st.W * Eigen::Map<const Eigen::VectorXd>(z.data(), Eigen::Index(z.size()));
    Derivatives dn;
    if (!ev.derivatives(next.data(), dn, true, false, nullptr) ||
        dn.log_likelihood < st.d.log_likelihood) {
      // no progress possible from here (Ceres kept the start): stop with what we have
      break;
    }
    ++s.gradient_evaluations;
    const bool moved = dn.log_likelihood > st.d.log_likelihood;
    st.theta = next;
    st.d = std::move(dn);
    if (!moved) break;
  }
  st.W = whitening(p, st.d.fisher, where);
  st.step_se = newton_step_se(st.W, st.d.gradient);
  s.converged = st.step_se < o.step_tolerance;
  return st;
}

/// Covariance of θ (internal scale) at the optimum.
Eigen::MatrixXd internal_covariance(const Evaluator& ev, const FitState& st, const RefineOptions& o,
                                    Summary& s) {
  const Eigen::Index n = st.theta.size();
  const Eigen::MatrixXd& W = st.W;
  Eigen::MatrixXd Finv = W * W.transpose();
  if (o.covariance == Covariance::Fisher) {
    s.covariance = "fisher";
    Eigen::LLT<Eigen::MatrixXd> llt(st.d.fisher);
    return llt.info() == Eigen::Success ? Eigen::MatrixXd(llt.solve(Eigen::MatrixXd::Identity(n, n)))
                                        : Finv;
  }
  // observed information in whitened coordinates by forward differences of the gradient (at
  // the optimum the gradient is ~0; the error is O(h) third derivatives, h = 0.01 SE)
  const double h = 1e-2;
  Eigen::MatrixXd Hz(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const Eigen::VectorXd tp = st.theta + h * W.col(j);
    Derivatives dp;
    s.gradient_evaluations += 1;
    if (!ev.derivatives(tp.data(), dp, false, false, nullptr)) {
      s.covariance = "fisher (observed information failed: the filter failed near the optimum)";
      return Finv;
    }
    Hz.col(j) = -(W.transpose() * (dp.gradient - st.d.gradient)) / h;
  }
  Hz = 0.5 * (Hz + Hz.transpose()).eval();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Hz);
  if (es.info() != Eigen::Success || es.eigenvalues().minCoeff() <= 1e-8) {
    s.covariance = "fisher (the observed information is not positive definite)";
    return Finv;
  }
  const Eigen::MatrixXd Hzinv = es.eigenvectors() * es.eigenvalues().cwiseInverse().asDiagonal() *
                                es.eigenvectors().transpose();
  if (o.covariance == Covariance::Observed) {
    s.covariance = "observed";
    return W * Hzinv * W.transpose();
  }
  Derivatives db = derivatives_or_throw(ev, st.theta, true, "sandwich scores");
  ++s.gradient_evaluations;
  const Eigen::MatrixXd Bz = W.transpose() * (db.batch_scores.transpose() * db.batch_scores) * W;
  s.covariance = "sandwich (" + std::to_string(db.batch_scores.rows()) + " batches)";
  return W * (Hzinv * Bz * Hzinv) * W.transpose();
}

/// A moment fit can have a diffusion polynomial that turns negative inside the data's range
/// (issue 12: 2Q < 0 at coarse sampling), where the filter cannot start. Then every
/// non-constant diffusion term restarts at a tiny positive value (kept as a parameter) and the
/// constant at the model's mean a22 over the data.
void repair_diffusion(ObservedModel& start, const Dataset& data) {
  double mean = 0.0;
  for (double x : data.x) mean += std::max(start.model.a22(x, 0.0), 0.0);
  mean /= double(data.x.size());
  if (!(mean > 0.0)) mean = 1e-6;
  bool has_constant = false;
  for (auto& tc : start.model.diffusion) {
    if (tc.term == Term::monomial(0, 0)) {
      tc.coef = mean;
      has_constant = true;
    } else if (tc.coef != 0.0) {
      tc.coef = 1e-6 * mean;
    }
  }
  if (!has_constant) {
    start.model.diffusion.push_back({Term::monomial(0, 0), mean});
    canonicalize(start.model.diffusion, "likelihood: start model");
  }
}

/// Removes the drift terms of degree above 3 that are not kept; false when there were none.
bool drop_high_degree_drift(ObservedModel& start, const std::vector<Term>& keep) {
  TermList& d = start.model.drift;
  const auto high = [&](const TermCoef& tc) {
    return tc.term.is_polynomial() && tc.term.px + tc.term.py > 3 && std::find(keep.begin(), keep.end(), tc.term) == keep.end();
  };
  const std::size_t before = d.size();
  d.erase(std::remove_if(d.begin(), d.end(), high), d.end());
  return d.size() != before;
}

/// The start the filter can run: a negative diffusion repaired (repair_diffusion); a drift whose
/// filter diverges at the data — a moment fit at coarse sampling or under heavy sensor noise
/// with x⁵ … x¹⁰ in place of x³ (a second outside tester: ω·Δt 0.2, and 5 % noise at 0.05) —
/// restarted without its terms of degree above 3 (the selection's forward steps add back what
/// the data need). A start that still fails is reported.
void repair_start(ObservedModel& start, const Dataset& data, const RefineOptions& o) {
  bool diffusion_repaired = false;
  for (;;) {
    try {
      (void)log_likelihood(start, data, o.filter);
      return;
    } catch (const Error& e) {
      const std::string what = e.what();
      if (!diffusion_repaired && what.find("a22 < 0") != std::string::npos) {
        repair_diffusion(start, data);
        diffusion_repaired = true;
      } else if (drop_high_degree_drift(start, o.keep_drift)) {
        if (o.log) o.log("likelihood: the start's filter diverges (" + what + "); restarted without its drift terms of degree > 3");
      } else {
        throw;
      }
    }
  }
}

}  // namespace

namespace detail {

/// One maximum-likelihood fit of a fixed support.
Result fit_support(const ObservedModel& start, const Dataset& data, const RefineOptions& o,
                   const FitChoice& choice, bool final_covariance) {
  const auto t0 = Clock::now();
  const std::string where = "likelihood";
  const Parameterization p(start, choice, data.records.size(), where);
  Evaluator ev(p, data, o.filter, where);
  if (o.sandwich_batch > 0) {
    ev.batch_samples = o.sandwich_batch;
  } else if (data.records.size() < 50) {
    ev.batch_samples = std::max<std::size_t>(16, (data.x.size() + 49) / 50);
  }
  Result res;
  Summary& s = res.summary;
  s.observations = ev.observations();
  s.blocks = ev.blocks().size();
  s.parameters = p.size();
  s.substeps = ev.settings().substeps;
  s.threads = ev.threads();
  Eigen::VectorXd theta = Eigen::Map<const Eigen::VectorXd>(p.initial().data(), Eigen::Index(p.size()));
  {
    double ll0 = 0.0;
    EvaluationFailure f;
    if (!ev.value(theta.data(), ll0, &f)) throw FilterDiverged(ev.message(f) + " (at the start values)");
    s.initial_log_likelihood = ll0;
  }
  if (ev.observations() > o.warm_start_samples) {
    // warm start on an eighth of the data (recursively, down to warm_start_samples); kept only
    // when the filter runs on all the data from there (a fit to a part can be unstable elsewhere)
    const Dataset sub = warm_start_share(data, 0.125, p.local_phase());
    if (2 * sub.x.size() <= data.x.size()) {  // (records too short to share: no warm start)
      RefineOptions so = o;
      so.filter.substeps = ev.settings().substeps;
      so.log = {};
      // the forcing frequency is held: a share of the records resolves it 8x more coarsely than
      // all of them, and the likelihood in omega has side optima every 2π/T_record (a warm start
      // that moves omega by one of the share's standard errors lands beside the full data's peak)
      FitChoice warm_choice = choice;
      for (const ParameterInfo& info : p.parameters())
        if (info.name == "harmonic_forcing.omega") warm_choice.fixed.push_back(info.name);
      try {
        const ObservedModel warm = fit_support(start, sub, so, warm_choice, false).model;
        const Parameterization pw(warm, choice, data.records.size(), where);
        double ll = 0.0;
        if (ev.value(pw.initial().data(), ll, nullptr) && ll > s.initial_log_likelihood)
          theta = Eigen::Map<const Eigen::VectorXd>(pw.initial().data(), Eigen::Index(pw.size()));
      } catch (const Error&) {
        // the warm start failed on the part: start from the given values
      }
    }
  }
  FitState st = maximise(ev, theta, o, s, where);
  s.final_log_likelihood = st.d.log_likelihood;
  s.newton_step_se = st.step_se;
  Eigen::MatrixXd cov;
  if (final_covariance) {
    cov = internal_covariance(ev, st, o, s);
  } else {
    s.covariance = "fisher";
    cov = st.W * st.W.transpose();
  }
  // natural scale
  const Eigen::Index n = st.theta.size();
  Eigen::VectorXd J(n);
  for (Eigen::Index i = 0; i < n; ++i) J[i] = p.jacobian(std::size_t(i), st.theta[i]);
  res.covariance = J.asDiagonal() * cov * J.asDiagonal();
  const std::vector<double> th(st.theta.data(), st.theta.data() + n);
  res.model = p.model_at(th);
  res.parameters = p.parameters();
  res.values.resize(std::size_t(n));
  res.stderrs.resize(std::size_t(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    res.values[std::size_t(i)] = p.natural(std::size_t(i), st.theta[i]);
    res.stderrs[std::size_t(i)] = std::sqrt(std::max(res.covariance(i, i), 0.0));
  }
  attach_stderrs(res);
  res.log_likelihood = st.d.log_likelihood;
  res.bic = -2.0 * res.log_likelihood + double(n) * std::log(double(ev.observations()));
  s.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  if (o.log) o.log(s.BriefReport());
  if (o.step) o.step();
  return res;
}

}  // namespace detail

Result refine(const ObservedModel& start, const Dataset& data, const RefineOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw Error("likelihood: " + why);
  validate_model(start.model, "likelihood: start model");
  if (!options.per_record_phase && !start.record_phases.empty())
    throw Error("likelihood: the start model has one harmonic_forcing phase per record (record_phases) but "
                "per_record_phase is false: the fit would use the shared phase in every record");
  ObservedModel first = start;
  detail::FitChoice choice;
  choice.fit_measurement_noise = options.estimate_measurement_noise;
  choice.per_record_phase = options.per_record_phase;
  choice.fixed = options.fixed;
  if (options.estimate_measurement_noise && !(first.measurement_sd > 0.0)) {
    first.measurement_sd = options.measurement_sd_start > 0.0 ? options.measurement_sd_start
                                                              : 0.01 * std::sqrt(detail::x_variance(data));
    if (!(first.measurement_sd > 0.0)) throw Error("likelihood: the records have zero variance");
  }
  repair_start(first, data, options);
  if (options.per_record_phase) detail::scan_record_phases(first, data, options.filter, choice);
  if (options.estimate_measurement_noise && !(start.measurement_sd > 0.0) && !(options.measurement_sd_start > 0.0))
    first.measurement_sd = detail::measurement_sd_start(first, data, options.filter, options.per_record_phase);
  first = detail::best_hidden_state_start(first, data, options, choice);
  Result res = options.select ? detail::select_support(first, data, options, choice)
                              : detail::fit_support(first, data, options, choice, true);
  detail::respect_domain(res);  // a negative amplitude flipped, other estimates outside the catalogue refused
  if (options.per_record_phase) {
    const double f = detail::correct_record_phase_bias(res);
    if (options.log && f != 1.0) {
      char line[160];
      std::snprintf(line, sizeof line, "likelihood: amplitude x %.5f for the free phases' bias (record_phase_bias.hpp)", f);
      options.log(line);
    }
  }
  const int noise = res.find("measurement_sd");
  choice.fit_measurement_noise = noise >= 0;
  // automatic only where the fitted sensor noise is resolved (fit_info.hpp)
  const bool noise_resolved =
      noise >= 0 && measurement_noise_resolved(res.values[std::size_t(noise)], res.stderrs[std::size_t(noise)]);
  if (options.bias_correction_datasets > 0 && !options.bias_correction_auto) {
    detail::correct_filter_bias(res, data, options, choice);
  } else if (options.bias_correction_datasets > 0 && noise_resolved && !options.per_record_phase) {
    try {
      detail::correct_filter_bias(res, data, options, choice);
    } catch (const Error& e) {
      res.summary.bias_correction_skipped = e.what();
      if (options.log) options.log("likelihood bias correction skipped: " + res.summary.bias_correction_skipped);
    }
  }
  detail::respect_domain(res);
  detail::attach_stderrs(res);  // the standard errors and the model's covariance from the final covariance
  return res;
}

}  // namespace vehs::likelihood

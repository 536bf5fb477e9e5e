#pragma once
// Maximum likelihood for an observed model (filter.hpp), started from a given model (in the
// product: identify's moment fit), with standard errors and optional selection of the support
// by a likelihood criterion. Ceres Solver does the optimisation (GradientProblemSolver, BFGS
// with a Wolfe line search) on automatic derivatives through the filter (ceres::Jet); nothing
// here is a hand-written optimiser.
//
// Parameters: the start model's non-zero drift and diffusion coefficients, its dynamic effects'
// parameters, the measurement noise and (optionally) one harmonic_forcing phase per record —
// see parameters.hpp for names and the log scale of positive quantities.
//
// The optimiser is local: a start must lie in the basin of the optimum. Dynamic-effect
// parameters are the delicate ones — the likelihood in harmonic_forcing.omega has side lobes
// every 2π/T_record, so omega must start within about π/T_record (identify's spectral scan
// provides that); gaps, λ and τ tolerate starts 20 % off (tests/likelihood/test_effects.cpp).
// A start whose diffusion turns negative inside the data (a moment fit at coarse sampling) is
// repaired: the non-constant a22 terms restart at tiny positive values.
//
// Conditioning. The optimiser works in whitened coordinates θ = θ₀ + W z with W Wᵀ the inverse
// Fisher information of the innovations at θ₀ (one derivative pass), so that a unit step is one
// standard error in every direction and BFGS's first step is a Fisher-scoring step; after each
// Ceres run the whitening is recomputed at the new point until the Newton step is below 0.01
// SE. Data larger than `warm_start_samples` are first fitted on the first eighth of every
// record (recursively), then on all of them (a few iterations from there); the warm start holds
// harmonic_forcing.omega (a share of the records cannot resolve it to the precision of all of
// them, and a side lobe is a local optimum). With one phase per record, every record's phase
// starts at the best of 12 values around its given start (the others at their start values).
//
// Standard errors (Options::covariance):
//  * observed  — inverse of the observed information, the Hessian of −log L by central
//                differences of the automatic gradient (2 gradient passes per parameter);
//  * fisher    — inverse Fisher information of the innovations, Σ ∂e∂eᵀ/S + ½∂S∂Sᵀ/S²
//                (no extra pass; equals observed in expectation under the model);
//  * sandwich  — H⁻¹ B H⁻¹ with B the covariance of score sums over contiguous batches (robust
//                to a misspecified noise model; needs many batches).
// On the natural scale by the delta method.
//
// Selection (Options::select): forward steps by the score test over candidate_drift /
// candidate_diffusion (below), then backward elimination from the support reached. At each step the
// free term (or the measurement noise) with the smallest |estimate/SE| is removed and the model
// refitted; the removal is kept when BIC = −2 log L + k log n does not increase (or, with the
// likelihood-ratio criterion, when 2ΔlogL is below the χ²₁ quantile at 1 − α; the measurement
// noise sits on the boundary, so there the ½χ²₀ + ½χ²₁ mixture is used). Two shortcuts save refits
// without changing what is removed: the free parameters with |z| < 2 are first removed together in
// one refit, kept removed when their joint 2ΔlogL is below the smallest single threshold (each
// one-at-a-time step on the way would then have passed: the models are nested, so every step's
// 2ΔlogL is at most the joint one), else removed one at a time; and a removal whose z² is above
// kWaldKeepFactor × threshold is kept without a refit (SelectionStep::by_wald). A term whose removal
// leaves a model the filter cannot start (an unstable or anti-damped drift at the data) is kept
// and the next candidate tried. Terms in keep_drift /
// keep_diffusion, diffusion[1] and effect parameters are never removed, nor the linear stiffness x
// and damping y of a model with an electromechanical state (which would stand in for them).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vehs/core/enum_names.hpp"
#include "vehs/core/dataset.hpp"
#include "vehs/likelihood/filter.hpp"
#include "vehs/likelihood/observed_model.hpp"
#include "vehs/likelihood/parameters.hpp"

namespace vehs::likelihood {

enum class Covariance { Observed, Fisher, Sandwich };
inline constexpr EnumNames<Covariance, 3> kCovarianceNames{
    {{Covariance::Observed, "observed"}, {Covariance::Fisher, "fisher"}, {Covariance::Sandwich, "sandwich"}}};

enum class SelectionCriterion { Bic, LikelihoodRatio };
inline constexpr EnumNames<SelectionCriterion, 2> kSelectionCriterionNames{
    {{SelectionCriterion::Bic, "bic"}, {SelectionCriterion::LikelihoodRatio, "lr"}}};

struct RefineOptions {
  FilterOptions filter;
  /// Estimate the measurement noise (log scale). Its start is the start model's measurement_sd,
  /// or `measurement_sd_start` when that is 0, or, when both are 0, the best by log-likelihood
  /// of 3 % … 0.01 % of std(x) (detail/measurement_noise_start.hpp).
  bool estimate_measurement_noise = true;
  double measurement_sd_start = 0.0;
  /// One harmonic_forcing phase per record (the start's record_phases, else scanned); the shared
  /// amplitude is returned corrected for the free phases' first-order bias
  /// (detail/record_phase_bias.hpp). A start with record_phases needs it (else an error).
  bool per_record_phase = false;
  std::vector<std::string> fixed;     ///< parameter names held at their start values
  Covariance covariance = Covariance::Observed;
  std::size_t sandwich_batch = 0;     ///< samples per batch (0: a record each, ≥ 50 batches)

  bool select = false;
  SelectionCriterion criterion = SelectionCriterion::Bic;
  double lr_alpha = 1e-3;
  std::vector<Term> keep_drift, keep_diffusion;
  /// Terms the selection may ADD before eliminating (identify's libraries): forward steps by
  /// the score test (score_test.hpp) at the current fit, the most significant term first, while
  /// its z² and then the refit's 2ΔlogL pass the criterion (at most `max_added` terms). The
  /// moment fit's support is only a start: white sensor noise of 5 % of std(x) made it drop the
  /// damping y, which the likelihood's own standard errors put at 10 SE.
  std::vector<Term> candidate_drift, candidate_diffusion;
  int max_added = 4;
  /// The forward step's score tests run on at most this many samples (whole records' leading
  /// shares); when none passes there (z² > max(f·bar, 9) on a share f), the three leading
  /// candidates are tested again on all the data.
  double screen_samples = 2e5;

  int max_iterations = 20;            ///< Ceres iterations per whitening round
  int max_rounds = 20;                ///< whitening rounds
  std::size_t warm_start_samples = 30000;  ///< larger data: first fitted on 1/8 of every record
  double step_tolerance = 0.01;       ///< convergence: Newton step below this many SE
  /// B > 0: the filter's own bias removed by simulation (detail/bias_correction.hpp): the
  /// estimate minus I⁻¹ × the mean score at it over B data sets simulated at it like the data;
  /// covariance × (1 + 1/B). 0: off. Costs B simulations and B gradient passes.
  int bias_correction_datasets = 0;
  std::uint64_t bias_correction_seed = 1;  ///< seed of the first simulated data set
  /// true (identify-vehs's `bias_correction: "auto"`): correct only when the final fit estimates and resolves (above 2 SE)
  /// the measurement noise and has one shared harmonic phase, and leave the fit uncorrected,
  /// with the reason in Summary::bias_correction_skipped, when the correction cannot be done
  /// (the estimate cannot be simulated or filtered on a simulated data set) instead of throwing.
  bool bias_correction_auto = false;
  /// Receives one line per fit and per selection step (the library itself never prints).
  std::function<void(const std::string&)> log;
  /// Called after each unit of work (every fit, warm starts and selection refits included, and
  /// every data set of the bias correction): progress reports count them.
  std::function<void()> step = {};

  bool IsValid(std::string* error) const;
};

struct SelectionStep {
  std::string removed;        ///< parameter name (a removal step)
  std::string added;          ///< parameter name (a forward step; `removed` empty)
  double z = 0.0;             ///< |estimate/SE| before removal; the score test's |z| before adding
  double log_likelihood = 0.0;  ///< of the model without it (with it, for a forward step)
  double delta = 0.0;         ///< 2 (log L_before − log L_after); 2 (log L_after − log L_before) when adding
  double threshold = 0.0;     ///< log n (BIC) or the χ² quantile (LR)
  bool accepted = false;
  int together = 1;           ///< terms removed in one refit with this one (delta is their joint 2ΔlogL)
  bool by_wald = false;       ///< kept without a refit: z² above kWaldKeepFactor × threshold (delta = z²)
};
/// A removal whose Wald z² exceeds this many times the criterion's threshold is decided (kept)
/// without its refit: 2ΔlogL ≈ z² near the optimum, and a factor 9 (z three times the bar's) leaves
/// room for the two to differ.
constexpr double kWaldKeepFactor = 9.0;

struct Summary {
  bool converged = false;
  std::string message;          ///< Ceres' termination message of the last round
  int rounds = 0, iterations = 0;
  int gradient_evaluations = 0, value_evaluations = 0;
  double initial_log_likelihood = 0.0, final_log_likelihood = 0.0;
  double newton_step_se = 0.0;  ///< size of the remaining Newton step in SE units
  double seconds = 0.0;
  int substeps = 0, threads = 0;
  std::size_t observations = 0, blocks = 0, parameters = 0;
  std::string covariance;       ///< method used (a failed observed falls back to fisher)
  std::vector<SelectionStep> selection;
  int bias_correction_datasets = 0;     ///< B of the bias correction (0: none)
  double bias_correction_max_se = 0.0;  ///< its largest shift, in the fit's SEs
  std::uint64_t bias_correction_seed = 0;  ///< seed of its first simulated data set
  std::string bias_correction_skipped;  ///< why an automatic correction was not done (empty: done or not asked)

  std::string BriefReport() const;
  std::string FullReport() const;
};

struct Result {
  /// The fitted model; standard errors in model.drift_stderr / diffusion_stderr /
  /// effects[i].stderr_; measurement_sd and record phases in the ObservedModel.
  ObservedModel model;
  std::vector<ParameterInfo> parameters;  ///< free parameters, in the order below
  std::vector<double> values, stderrs;    ///< natural scale
  Eigen::MatrixXd covariance;             ///< natural scale
  double log_likelihood = 0.0;
  double bic = 0.0;
  Summary summary;

  /// Index of a parameter by name, or −1.
  int find(const std::string& name) const;
};

/// Maximum likelihood from `start` (and selection when requested). Throws vehs::Error with one
/// line for invalid options, a model or data the filter cannot take, or a start model whose
/// filter diverges.
Result refine(const ObservedModel& start, const Dataset& data, const RefineOptions& options = {});

}  // namespace vehs::likelihood

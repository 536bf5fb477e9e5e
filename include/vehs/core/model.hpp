#pragma once
// The model of docs/model-file.md: dX = Y dt, dY = b2 dt + sqrt(a22) dB, plus named effects.
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "vehs/core/enum_names.hpp"
#include "vehs/core/fit_info.hpp"
#include "vehs/core/terms.hpp"

namespace vehs {

/// The effect catalogue (docs/reference/effects.md).
enum class EffectId {
  AsymmetricStiffness,        ///< even powers of x in the restoring force (term-like)
  CoulombFriction,            ///< −μ·sign(y) (term-like)
  QuadraticDamping,           ///< −c·y|y| (term-like)
  NonlinearDamping,           ///< −c_x2y·x²y − c_y3·y³ (term-like)
  ImpactStop,                 ///< extra stiffness k_stop beyond |x| > gap
  HarmonicForcing,            ///< + amplitude·cos(omega·t + phase)
  ElectromechanicalCoupling,  ///< hidden v: dv = (y − λ v) dt, force −coupling·v
  ColoredNoise,               ///< Ornstein–Uhlenbeck excitation η with correlation time τ
  VelocityDependentNoise,     ///< + q_y2·y² in a22 (term-like)
};

inline constexpr EnumNames<EffectId, 9> kEffectNames{{
    {EffectId::AsymmetricStiffness, "asymmetric_stiffness"},
    {EffectId::CoulombFriction, "coulomb_friction"},
    {EffectId::QuadraticDamping, "quadratic_damping"},
    {EffectId::NonlinearDamping, "nonlinear_damping"},
    {EffectId::ImpactStop, "impact_stop"},
    {EffectId::HarmonicForcing, "harmonic_forcing"},
    {EffectId::ElectromechanicalCoupling, "electromechanical_coupling"},
    {EffectId::ColoredNoise, "colored_noise"},
    {EffectId::VelocityDependentNoise, "velocity_dependent_noise"},
}};

struct EffectParamSpec {
  std::string_view name;
  std::string_view meaning;
  double lower_bound;  ///< parameter must be >= this (−inf when free)
  bool strictly_positive;
  std::optional<double> default_value;  ///< absent: required
};

struct EffectSpec {
  EffectId id;
  std::string_view name;
  std::string_view physics;  ///< one line: the force or noise it adds
  /// Term-like effects are plain dictionary terms; in a model file they live in drift /
  /// diffusion and are expanded from an `effects` entry on reading.
  bool term_like;
  std::vector<EffectParamSpec> params;
};

/// The catalogue, in the order of kEffectNames.
const std::vector<EffectSpec>& effect_catalogue();
const EffectSpec& effect_spec(EffectId id);

struct Effect {
  EffectId id{};
  std::map<std::string, double> params;
  std::map<std::string, double> stderr_;  ///< standard errors of fitted params (may be empty)

  std::string name() const { return enum_to_string(kEffectNames, id); }
  double param(const std::string& key) const;  ///< throws if missing
};

/// Drift / diffusion terms that a term-like effect stands for, with signs applied
/// (e.g. coulomb_friction{mu} -> {sign(y): −mu}). Empty for dynamic effects.
struct EffectTerms {
  TermList drift;
  TermList diffusion;
};
EffectTerms effect_terms(const Effect& effect);
/// The terms an effect adds, with every parameter at 1 (which terms a fit of the effect needs).
EffectTerms unit_effect_terms(EffectId id);

/// Covariance of a model's estimates (identify's sandwich estimator, or a likelihood fit), over
/// parameters named as in vehs/core/parameters.hpp: "drift[x^3]", "diffusion[1]" (the raw
/// coefficients, not beta or k_i) and "<effect>.<param>". The model file's key "covariance".
struct ParameterCovariance {
  std::vector<std::string> names;
  std::vector<double> matrix;  ///< row-major, names.size()² entries

  bool empty() const { return names.empty(); }
  std::size_t size() const { return names.size(); }
  double operator()(std::size_t i, std::size_t j) const { return matrix[i * names.size() + j]; }
  double& operator()(std::size_t i, std::size_t j) { return matrix[i * names.size() + j]; }
  /// Index of a name, or size() when absent.
  std::size_t index_of(std::string_view name) const;
  /// Empty when valid (square, finite, symmetric, non-negative diagonal, unique names), else a
  /// one-line reason.
  std::string invalid_reason() const;
};

struct Model {
  TermList drift;      ///< b2 = Σ coef·term
  TermList diffusion;  ///< a22 = Σ coef·term
  std::vector<Effect> effects;  ///< dynamic effects only (term-like ones are expanded)
  std::map<std::string, double> drift_stderr;      ///< by term name
  std::map<std::string, double> diffusion_stderr;  ///< by term name
  /// How the model was fitted (set by identify, read from the model file's "estimator" and
  /// "sampling"); empty for a model that was not fitted.
  std::optional<FitInfo> fit;
  /// Covariance of the estimates; empty when the model was not fitted (or the file has none).
  ParameterCovariance covariance;

  double drift_coef(std::string_view term) const;      ///< 0 when absent
  double diffusion_coef(std::string_view term) const;  ///< 0 when absent
  const Effect* find_effect(EffectId id) const;
  bool has_dynamic_effects() const { return !effects.empty(); }
  bool uses_drive() const;  ///< a `u` term is present

  double b2(double x, double y, double u = 0.0) const { return evaluate(drift, x, y, u); }
  double a22(double x, double y) const { return evaluate(diffusion, x, y, 0.0); }

  /// The paper's harvester (Eq. 7): b2 = −β y − Σ k_i x^i, a22 = 2D + 2Q x², with k given by
  /// power: {{1, k1}, {3, k3}, …} (vehs/core/model_builder.hpp builds any other model).
  static Model paper(double beta, const std::map<int, double>& k, double two_D, double two_Q = 0.0);
};

/// Whether a term may appear in the diffusion a22 (not the drive u, not sign(y)).
inline bool allowed_in_diffusion(const Term& t) { return !t.depends_on_u() && t.kind != TermKind::SignY; }

/// Empty when `key` is a parameter of the effect, else the reason as a suffix for an error
/// message (": effect 'x' has no parameter 'k' (its parameters: ...)").
std::string unknown_parameter(EffectId id, const std::string& key);

/// Checks an effect's parameters against the catalogue (known names, finite, within bounds) and
/// completes it: impact_stop's gap_neg defaults to gap; with `require_params` missing parameters
/// take their defaults or are an error. Returns an empty string, or the reason as a suffix for
/// an error message (": effect 'x' needs parameter 'y' (...)" or ".params.y must be > 0 ...").
std::string complete_effect(Effect& effect, bool require_params);

/// Empty when every parameter of the effect lies in its catalogue domain, else
/// "<effect>.<param> = <value> is outside its domain (>= 0)" for the first that does not
/// (what a model file refuses; complete_effect's bound check).
std::string effect_domain_violation(const Effect& effect);

/// Adds an effect to a model: a term-like effect becomes its drift / diffusion terms (an error
/// when a term is already there), a dynamic one is appended to Model::effects (an error when it
/// is already there). Its parameters are completed and checked first. Errors are prefixed with
/// `where`.
void add_effect(Model& model, Effect effect, const std::string& where);

/// Structural checks shared by every tool: finite coefficients, non-negative noise at the
/// origin, known effect params within bounds. Throws vehs::Error prefixed with `where`.
void validate_model(const Model& m, const std::string& where);

}  // namespace vehs

#pragma once
// A user's own effect (docs/model-file.md#user-effects): a named set of parameters, each the
// coefficient of one drift or diffusion term the user writes as an expression in x, y, u —
//   {"name": "directional_friction",
//    "drift": {"Fp": "-(y>0)", "Fm": "(y<0)", "cp": "-y*(y>0)", "cm": "-y*(y<0)"}}
// adds −Fp·1(y>0) + Fm·1(y<0) − cp·y·1(y>0) − cm·y·1(y<0) to the drift. identify fits its
// parameters as the coefficients of these terms (kept through every selection) with standard
// errors; diagnose tests it as a suspect beside the catalogue's effects (score test, held-out
// refit, confirmation) and recommends it by name. In a model file the effect is its terms.
#include <map>
#include <string>
#include <vector>

#include "vehs/core/model.hpp"
#include "vehs/core/terms.hpp"

namespace vehs {

struct UserEffectParam {
  std::string name;
  Term term;               ///< the parameter multiplies this term
  bool diffusion = false;  ///< a term of a22 (else of the drift b2)
};

struct UserEffect {
  std::string name;
  std::vector<UserEffectParam> params;

  /// Empty when valid, else a one-line reason: a name (not a catalogue effect's), at least one
  /// parameter, parameter names unique, every term once, diffusion terms allowed in a22.
  std::string invalid_reason() const;
  /// The terms the effect adds, every parameter at 1.
  EffectTerms unit_terms() const;
};

/// The effect's parameters read from a model's coefficients, with their standard errors.
struct UserEffectFit {
  std::string name;
  std::map<std::string, double> params, stderr_;
};
UserEffectFit user_effect_fit(const Model& model, const UserEffect& effect);

/// The user effect named `name` in `effects`, or nullptr.
const UserEffect* find_user_effect(const std::vector<UserEffect>& effects, const std::string& name);

}  // namespace vehs

#include "vehs/core/user_effect.hpp"

#include <algorithm>
#include <set>

namespace vehs {

std::string UserEffect::invalid_reason() const {
  if (name.empty()) return "a user effect needs a non-empty 'name'";
  for (const auto& spec : effect_catalogue())
    if (spec.name == name) return "'" + name + "' is a catalogue effect: give a user effect another name";
  if (params.empty()) return "user effect '" + name + "' needs at least one parameter in 'drift' or 'diffusion'";
  std::set<std::string> names;
  std::vector<std::pair<bool, Term>> terms;
  for (const auto& p : params) {
    if (!names.insert(p.name).second) return "user effect '" + name + "': parameter '" + p.name + "' is given twice";
    const std::pair<bool, Term> key{p.diffusion, p.term};
    if (std::find(terms.begin(), terms.end(), key) != terms.end())
      return "user effect '" + name + "': the term '" + p.term.name() + "' belongs to two parameters";
    terms.push_back(key);
    if (p.diffusion && !allowed_in_diffusion(p.term))
      return "user effect '" + name + "': '" + p.term.name() + "' is not allowed in the diffusion";
  }
  return "";
}

EffectTerms UserEffect::unit_terms() const {
  EffectTerms t;
  for (const auto& p : params) (p.diffusion ? t.diffusion : t.drift).push_back({p.term, 1.0});
  return t;
}

UserEffectFit user_effect_fit(const Model& model, const UserEffect& effect) {
  UserEffectFit f{effect.name, {}, {}};
  for (const auto& p : effect.params) {
    f.params[p.name] = coefficient(p.diffusion ? model.diffusion : model.drift, p.term);
    const auto& se = p.diffusion ? model.diffusion_stderr : model.drift_stderr;
    if (const auto it = se.find(p.term.name()); it != se.end()) f.stderr_[p.name] = it->second;
  }
  return f;
}

const UserEffect* find_user_effect(const std::vector<UserEffect>& effects, const std::string& name) {
  for (const auto& e : effects)
    if (e.name == name) return &e;
  return nullptr;
}

}  // namespace vehs
